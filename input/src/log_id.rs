//! Log ids read from input files (`--log-prompts`, prediction and ground-truth keys, tracker
//! pickles, timestamps): every one is joined to a dataset directory somewhere, so one that is
//! not a plain name (a path separator, `..`, an absolute path) would read outside it.

/// The longest log id accepted (AV2 ids are 36 characters).
pub const MAX_LOG_ID_LEN: usize = 128;

/// Checks that `id` can name a log directory: non-empty, at most [`MAX_LOG_ID_LEN`] bytes, only
/// ASCII letters, digits, `-`, `_` and `.`, and not starting with `.` (so never `..`, a hidden
/// name, a separator or an absolute path). AV2's ids (`3b3570b4-7b0b-3268-a571-b0889dbf40b6`)
/// pass; the error names the id and what is wrong with it.
pub fn check_log_id(id: &str) -> Result<(), String> {
    let problem = if id.is_empty() {
        Some("is empty".to_string())
    } else if id.len() > MAX_LOG_ID_LEN {
        Some(format!("is longer than {MAX_LOG_ID_LEN} bytes"))
    } else if id.starts_with('.') {
        Some("starts with `.` (a relative path such as `..`?)".to_string())
    } else {
        id.chars()
            .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.')))
            .map(|c| match c {
                '/' | '\\' => format!("contains the path separator {c:?}"),
                c => format!("contains {c:?}"),
            })
    };
    match problem {
        None => Ok(()),
        Some(p) => Err(format!(
            "log id {id:?} {p}: a log id is a directory name such as \
             3b3570b4-7b0b-3268-a571-b0889dbf40b6 (letters, digits, `-`, `_`, `.`)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn av2_ids_pass_paths_do_not() {
        assert!(check_log_id("3b3570b4-7b0b-3268-a571-b0889dbf40b6").is_ok());
        assert!(check_log_id("log_7.copy").is_ok());
        for (id, why) in [
            ("../../elsewhere/log", "starts with `.`"),
            ("..", "starts with `.`"),
            ("/etc", "path separator '/'"),
            ("a/../../b", "path separator '/'"),
            ("a\\b", "path separator '\\\\'"),
            ("", "is empty"),
            ("a\0b", "contains '\\0'"),
        ] {
            let e = check_log_id(id).expect_err(id);
            assert!(e.contains(&format!("{id:?}")), "{e}");
            assert!(e.contains(why), "{id}: {e}");
        }
        assert!(check_log_id(&"a".repeat(MAX_LOG_ID_LEN + 1)).is_err());
    }
}
