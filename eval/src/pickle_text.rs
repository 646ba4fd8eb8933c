//! The text arguments of pickle protocols 0 and 1 (what `pickle.dump(obj, f, protocol=0)`
//! writes): `UNICODE` lines in Python's raw-unicode-escape, `STRING` lines as a quoted `repr`.

/// Decodes a raw-unicode-escape line: bytes are Latin-1 characters except `\uXXXX` and
/// `\UXXXXXXXX` escapes (pickle escapes `\`, NUL, CR, LF and ^Z that way).
pub(crate) fn raw_unicode_escape(line: &[u8]) -> Result<String, String> {
    let mut out = String::with_capacity(line.len());
    let mut i = 0;
    while i < line.len() {
        let b = line[i];
        let digits = match (b, line.get(i + 1)) {
            (b'\\', Some(b'u')) => 4,
            (b'\\', Some(b'U')) => 8,
            _ => 0,
        };
        if digits == 0 {
            out.push(char::from(b));
            i += 1;
            continue;
        }
        let hex = line
            .get(i + 2..i + 2 + digits)
            .and_then(|h| std::str::from_utf8(h).ok())
            .ok_or("a truncated \\u escape")?;
        let code = u32::from_str_radix(hex, 16).map_err(|_| format!("bad escape \\u{hex}"))?;
        out.push(char::from_u32(code).ok_or(format!("invalid code point {code:#x}"))?);
        i += 2 + digits;
    }
    Ok(out)
}

/// Decodes a `STRING` argument: a Python bytes `repr` in single or double quotes, with its
/// backslash escapes (`\\`, `\'`, `\"`, `\n`, `\r`, `\t`, `\xNN`).
pub(crate) fn quoted_string(line: &[u8]) -> Result<Vec<u8>, String> {
    let inner = match line {
        [q @ (b'\'' | b'"'), inner @ .., last] if last == q => inner,
        _ => return Err("a STRING argument without quotes".into()),
    };
    let mut out = Vec::with_capacity(inner.len());
    let mut i = 0;
    while i < inner.len() {
        if inner[i] != b'\\' {
            out.push(inner[i]);
            i += 1;
            continue;
        }
        let esc = *inner.get(i + 1).ok_or("a STRING ending in a backslash")?;
        i += 2;
        out.push(match esc {
            b'n' => b'\n',
            b'r' => b'\r',
            b't' => b'\t',
            b'0' => 0,
            b'x' => {
                let hex = inner
                    .get(i..i + 2)
                    .and_then(|h| std::str::from_utf8(h).ok())
                    .ok_or("a truncated \\x escape")?;
                i += 2;
                u8::from_str_radix(hex, 16).map_err(|_| format!("bad escape \\x{hex}"))?
            }
            other => other,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn protocol_zero_strings() {
        assert_eq!(raw_unicode_escape(b"ab\\u005cc").unwrap(), "ab\\c");
        assert_eq!(raw_unicode_escape(b"\\u000a\\U0001f600").unwrap(), "\n😀");
        assert_eq!(raw_unicode_escape(&[0xe9]).unwrap(), "é");
        assert!(raw_unicode_escape(b"\\u12").is_err());
        assert_eq!(quoted_string(b"'a\\'b\\x00'").unwrap(), b"a'b\0");
        assert_eq!(quoted_string(b"\"x\\n\"").unwrap(), b"x\n");
        assert!(quoted_string(b"'open").is_err());
    }
}
