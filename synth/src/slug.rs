//! File names from descriptions: lower-case ASCII words joined by `-`.

/// Longest slug, in bytes.
pub const MAX_SLUG: usize = 80;

/// A file-name slug of a description: ASCII letters and digits lower-cased, every other run of
/// characters one `-`, at most [`MAX_SLUG`] bytes (cut at a word boundary when there is one);
/// `"description"` when nothing is left.
pub fn slug(description: &str) -> String {
    let mut out = String::new();
    let mut dash = false;
    for c in description.chars() {
        if c.is_ascii_alphanumeric() {
            if dash && !out.is_empty() {
                out.push('-');
            }
            dash = false;
            out.push(c.to_ascii_lowercase());
        } else {
            dash = true;
        }
    }
    if out.len() > MAX_SLUG {
        out.truncate(MAX_SLUG);
        if let Some(i) = out.rfind('-').filter(|&i| i > MAX_SLUG / 2) {
            out.truncate(i);
        }
        while out.ends_with('-') {
            out.pop();
        }
    }
    if out.is_empty() {
        out.push_str("description");
    }
    out
}

/// Slugs for a list of descriptions, made unique in order (`-2`, `-3`, … on collisions).
pub fn unique_slugs<S: AsRef<str>>(descriptions: &[S]) -> Vec<String> {
    let mut seen = std::collections::HashSet::new();
    descriptions
        .iter()
        .map(|d| {
            let base = slug(d.as_ref());
            let mut s = base.clone();
            let mut n = 1;
            while !seen.insert(s.clone()) {
                n += 1;
                s = format!("{base}-{n}");
            }
            s
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slugs() {
        assert_eq!(
            slug("Vehicle making a LEFT turn"),
            "vehicle-making-a-left-turn"
        );
        assert_eq!(slug("  ego, near (3+) peds!  "), "ego-near-3-peds");
        assert_eq!(slug("ÉÉ ~~~"), "description");
        assert_eq!(slug("café au lait"), "caf-au-lait");
        let long = "word ".repeat(40);
        let s = slug(&long);
        assert!(
            s.len() <= MAX_SLUG && !s.ends_with('-') && s.ends_with("word"),
            "{s}"
        );
        let one = "x".repeat(200);
        assert_eq!(slug(&one).len(), MAX_SLUG);
    }

    #[test]
    fn unique_in_order() {
        assert_eq!(
            unique_slugs(&["a b", "A-B", "a b!", "c"]),
            ["a-b", "a-b-2", "a-b-3", "c"]
        );
    }
}
