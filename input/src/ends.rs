//! What the first and last bytes of each input format must be, checked by
//! [`crate::file::read_file_checking_ends`] before a file is read whole: a file of another
//! format, or one padded to gigabytes (`truncate -s 20G`), is an error at once.

/// The magic bytes at both ends of an Arrow IPC file (feather v2).
const ARROW_MAGIC: &[u8] = b"ARROW1";

/// An Arrow IPC file starts and ends with `ARROW1`.
pub fn arrow_ends(head: &[u8], tail: &[u8]) -> Result<(), String> {
    if !head.starts_with(ARROW_MAGIC) {
        return Err(
            "is not an Arrow IPC (feather v2) file: it does not start with `ARROW1`".into(),
        );
    }
    if !tail.ends_with(ARROW_MAGIC) {
        return Err(
            "is not a whole Arrow IPC (feather v2) file: it does not end with `ARROW1` (cut short, \
             or followed by other bytes)"
                .into(),
        );
    }
    Ok(())
}

/// A pickle ends with its STOP opcode (`.`), whatever its protocol: `pickle.dump` writes
/// nothing after it.
pub fn pickle_ends(_head: &[u8], tail: &[u8]) -> Result<(), String> {
    match tail.last() {
        Some(b'.') => Ok(()),
        Some(_) => Err(
            "is not a readable pickle: it does not end with the STOP opcode `.` (cut short, or \
             followed by other bytes)"
                .into(),
        ),
        None => Err("is empty: not a readable pickle".into()),
    }
}

/// A JSON document whose top level is an object: its first non-blank byte is `{` (a head that is
/// all blank is not judged), and its end holds no NUL byte (JSON text never does; a file padded
/// with zeros does). A document merely cut short is left to the JSON parser, whose error says
/// where.
pub fn json_object_ends(head: &[u8], tail: &[u8]) -> Result<(), String> {
    let blank = |b: &&u8| b.is_ascii_whitespace();
    if let Some(&first) = head.iter().find(|b| !blank(b)) {
        if first != b'{' {
            return Err(format!(
                "is not a JSON object: it starts with {:?}, not `{{`",
                char::from(first)
            ));
        }
    }
    if tail.contains(&0) {
        return Err(
            "is not JSON text: it ends in NUL bytes (a file padded with zeros?)".to_string(),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_format_accepts_its_ends_and_names_what_is_wrong() {
        assert!(arrow_ends(b"ARROW1\0\0", b"\0\0ARROW1").is_ok());
        assert!(arrow_ends(b"PAR1", b"ARROW1").is_err());
        let padded = arrow_ends(b"ARROW1\0\0", &[0; 64]).expect_err("padded");
        assert!(padded.contains("does not end"), "{padded}");
        assert!(pickle_ends(b"\x80\x04", b"\x94.").is_ok());
        assert!(pickle_ends(b"(dp0", b"s.").is_ok(), "protocol 0");
        assert!(pickle_ends(b"\x80\x04", &[0; 64]).is_err());
        assert!(pickle_ends(b"", b"").is_err());
        assert!(json_object_ends(b"  {\"a\": 1", b"1}\n").is_ok());
        assert!(json_object_ends(b"   ", b"  ").is_ok());
        assert!(json_object_ends(b"[1]", b"]").is_err());
        let nul = json_object_ends(b"{\"a\"", &[0; 64]).expect_err("padded");
        assert!(nul.contains("NUL"), "{nul}");
        assert!(
            json_object_ends(b"{\"a\"", b"\"a\": [1, 2").is_ok(),
            "cut: the parser says where"
        );
    }
}
