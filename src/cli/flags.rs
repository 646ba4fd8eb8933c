//! Parsers for numeric command-line flags that clap's built-in ones do not cover: a float flag
//! must be a finite number in its range, so `NaN`, `inf` or a negative distance is an error
//! naming the flag instead of a silently different answer.

/// A finite number greater than zero (a distance such as `--max-range-m`).
pub fn positive_finite(text: &str) -> Result<f64, String> {
    let x = finite(text)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("expected a number greater than 0, got {x}"))
    }
}

/// A finite number zero or greater (a time such as `--at` seconds).
pub fn non_negative_finite(text: &str) -> Result<f64, String> {
    let x = finite(text)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err(format!("expected a number 0 or greater, got {x}"))
    }
}

fn finite(text: &str) -> Result<f64, String> {
    let x: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("expected a number, got {text:?}"))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("expected a finite number, got {text:?}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_must_be_finite_and_in_range() {
        assert_eq!(positive_finite("50"), Ok(50.0));
        assert_eq!(positive_finite(" 12.5 "), Ok(12.5));
        for bad in [
            "NaN", "nan", "inf", "-inf", "infinity", "0", "-3", "", "fifty", "1e999",
        ] {
            assert!(positive_finite(bad).is_err(), "{bad:?} accepted");
        }
        assert_eq!(non_negative_finite("0"), Ok(0.0));
        assert_eq!(non_negative_finite("3.5"), Ok(3.5));
        for bad in ["NaN", "inf", "-0.1", "-1e300"] {
            assert!(non_negative_finite(bad).is_err(), "{bad:?} accepted");
        }
    }
}
