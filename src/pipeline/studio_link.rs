//! The address at which `scenalog studio` opens one match: a program by name, a log, a track and
//! a time, in the page's fragment (`#program=…&log=…&track=…&t=…`), which the page reads on load.
//! `mine` prints one and the report links every match, so a match found in a run opens in the
//! studio started on the run's rules and logs.

/// The port `scenalog studio` listens on unless told another.
pub const DEFAULT_PORT: u16 = 7878;

/// Percent-encodes what is not a letter, digit or one of `-._~` (a fragment's value).
fn encode(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for b in s.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// The studio's address (on its default port) that opens `program` on `log_id` with `track`
/// selected at `seconds` from the log's start.
pub fn studio_url(program: &str, log_id: &str, track: &str, seconds: f64) -> String {
    format!(
        "http://127.0.0.1:{DEFAULT_PORT}/#program={}&log={}&track={}&t={seconds:.1}",
        encode(program),
        encode(log_id),
        encode(track)
    )
}

/// The `scenalog studio` command that offers a run's programs (their folders) and opens its
/// logs, so that [`studio_url`]'s addresses of the run's matches open.
pub fn studio_command<'a>(
    programs: impl IntoIterator<Item = &'a std::path::Path>,
    logs: impl IntoIterator<Item = &'a std::path::Path>,
) -> String {
    let mut folders: Vec<String> = Vec::new();
    for p in programs {
        let folder = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.display().to_string(),
            _ => ".".to_string(),
        };
        if !folders.contains(&folder) {
            folders.push(folder);
        }
    }
    let logs: Vec<String> = logs.into_iter().map(|l| l.display().to_string()).collect();
    format!(
        "scenalog studio --rules {} --logs {}",
        folders.join(" "),
        logs.join(" ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names with characters a fragment cannot hold are encoded; the page decodes them with
    /// `URLSearchParams`, which undoes exactly this.
    #[test]
    fn names_are_encoded_and_time_kept_to_a_tenth() {
        assert_eq!(
            studio_url("stopped_car", "3bffdcff-c3a7", "04a25b36", 10.26),
            "http://127.0.0.1:7878/#program=stopped_car&log=3bffdcff-c3a7&track=04a25b36&t=10.3"
        );
        assert_eq!(
            studio_url("a b&c=d#é", "l", "t", 0.0),
            "http://127.0.0.1:7878/#program=a%20b%26c%3Dd%23%C3%A9&log=l&track=t&t=0.0"
        );
    }
}
