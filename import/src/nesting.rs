//! How deeply a Python program could nest, measured on its text before it is parsed: the Python
//! parser, the translation and dropping the syntax tree all recurse once per level of the tree, so
//! a program nesting calls 10,000 deep would overflow the stack. Two counts bound the tree's
//! height: the nesting of brackets, and per statement the tokens that can each add a level
//! (operators, `.`, calls and subscripts, `not`, `lambda`, `if`/`else`, …). A program past either
//! limit is an error for its file, found in one pass over the text without recursion.

/// Most brackets (`(`, `[`, `{`) open at once. RefAV programs nest a handful (a call of a call
/// of `scenario_not(...)`); CPython itself refuses 200.
pub const MAX_BRACKETS: usize = 64;

/// Most tokens that can nest the tree (operators, `.`, `not`, `lambda`, `if`, `else`, …; a `(`
/// counts 4, a `[` 2) in one statement. RefAV statements are a call or two with keyword arguments
/// (under 60).
pub const MAX_NESTING_TOKENS: usize = 500;

/// What was too deep, and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TooDeep {
    /// The byte offset of the token that passed the limit.
    pub offset: usize,
    /// What was counted and the limit, in words.
    pub what: String,
}

/// The first place `source` passes [`MAX_BRACKETS`] or [`MAX_NESTING_TOKENS`], if any. Strings
/// (single, double, triple-quoted, with escapes) and comments are skipped; a statement ends at a
/// newline outside brackets (not after `\`) or at `;`.
pub fn too_deep(source: &str) -> Option<TooDeep> {
    let bytes = source.as_bytes();
    let mut depth = 0usize;
    let mut tokens = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b'#' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'\'' | b'"' => {
                i = string_end(bytes, i);
                continue;
            }
            b'\\' => {
                // A line continuation (or a stray backslash): the statement goes on.
                i += 2;
                continue;
            }
            b'\n' if depth == 0 => tokens = 0,
            b';' if depth == 0 => tokens = 0,
            b'(' | b'[' | b'{' => {
                depth += 1;
                // A call costs the translation about four times an operator's stack, a subscript
                // twice (measured on a 2 MiB thread: the test below).
                tokens += match b {
                    b'(' => 4,
                    b'[' => 2,
                    _ => 0,
                };
                if depth > MAX_BRACKETS {
                    return Some(TooDeep {
                        offset: i,
                        what: format!("brackets nested more than {MAX_BRACKETS} deep"),
                    });
                }
            }
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            b'+' | b'-' | b'*' | b'/' | b'%' | b'@' | b'&' | b'|' | b'^' | b'~' | b'<' | b'>'
            | b'=' | b'!' | b'.' | b':' => tokens += 1,
            _ if b.is_ascii_alphabetic() || b == b'_' => {
                let start = i;
                while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                    i += 1;
                }
                let word = &source[start..i];
                if matches!(
                    word,
                    "not" | "lambda" | "if" | "else" | "and" | "or" | "await" | "in" | "is"
                ) {
                    tokens += 1;
                }
                // A string prefix (`f'…'`, `rb"…"`) is read with its string.
                if i < bytes.len() && matches!(bytes[i], b'\'' | b'"') && start + 2 >= i {
                    i = string_end(bytes, i);
                }
                if tokens > MAX_NESTING_TOKENS {
                    return Some(too_many(start));
                }
                continue;
            }
            _ => {}
        }
        if tokens > MAX_NESTING_TOKENS {
            return Some(too_many(i));
        }
        i += 1;
    }
    None
}

fn too_many(offset: usize) -> TooDeep {
    TooDeep {
        offset,
        what: format!(
            "a statement of more than {MAX_NESTING_TOKENS} operators, calls, attributes and \
             keywords that nest its expression"
        ),
    }
}

/// The index just past the string literal whose opening quote is at `start` (the end of the
/// text when it is not closed; a one-line string also ends at its line's end).
fn string_end(bytes: &[u8], start: usize) -> usize {
    let q = bytes[start];
    let triple = bytes.get(start + 1) == Some(&q) && bytes.get(start + 2) == Some(&q);
    let mut i = start + if triple { 3 } else { 1 };
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'\n' if !triple => return i,
            c if c == q => {
                if !triple {
                    return i + 1;
                }
                if bytes.get(i + 1) == Some(&q) && bytes.get(i + 2) == Some(&q) {
                    return i + 3;
                }
                i += 1;
            }
            _ => i += 1,
        }
    }
    bytes.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brackets_past_the_limit_are_found_where_they_pass_it() {
        let ok = format!("x = {}1{}\n", "(".repeat(64), ")".repeat(64));
        assert_eq!(too_deep(&ok), None);
        let deep = format!("x = {}1{}\n", "f(".repeat(65), ")".repeat(65));
        let found = too_deep(&deep).map(|t| t.offset);
        assert_eq!(found, Some(4 + 64 * 2 + 1));
    }

    #[test]
    fn strings_and_comments_do_not_count() {
        let src = format!(
            "x = '{0}'\ny = \"\"\"{0}\n{0}\"\"\"\n# {0}\nz = f'{0}' + r\"\\\"{0}\"\n",
            "(".repeat(500)
        );
        assert_eq!(too_deep(&src), None);
    }

    #[test]
    fn long_chains_of_operators_in_one_statement_are_found() {
        let chain = format!("x = {}\n", vec!["a"; 600].join(" + "));
        assert!(too_deep(&chain).is_some());
        let nots = format!("x = {}a\n", "not ".repeat(600));
        assert!(too_deep(&nots).is_some());
        // The count starts again at each statement.
        let many = "x = a + b\n".repeat(5_000);
        assert_eq!(too_deep(&many), None);
    }

    /// Just within the limits, every form of nesting is translated (or refused by the
    /// translation) on a thread of 2 MiB, the smallest stack a caller gives it (a test thread):
    /// the limits leave the recursion of parsing, translating and dropping room to spare.
    #[test]
    fn programs_just_within_the_limits_fit_a_small_stack() {
        let n = MAX_NESTING_TOKENS - 10;
        let forms = [
            format!("{}vehicles{}", "scenario_not(".repeat(64), ")".repeat(64)),
            format!("{}vehicles{}", "scenario_not(-".repeat(60), ")".repeat(60)),
            format!("{}vehicles", "not ".repeat(n)),
            format!("{}vehicles", "-".repeat(n)),
            vec!["vehicles"; n].join(" + "),
            vec!["vehicles"; n / 2].join(" ** "),
            format!("vehicles{}", ".a".repeat(n / 2)),
            format!("vehicles{}", "[0]".repeat(n / 2)),
            format!("vehicles{}", "()".repeat(n / 4)),
            format!("{}vehicles", "vehicles if is_gt else ".repeat(n / 2)),
            format!("{}vehicles", "lambda: ".repeat(n / 2)),
        ];
        for form in forms {
            let src = format!(
                "vehicles = get_objects_of_category(log_dir, category='VEHICLE')\nresult = \
                 {form}\noutput_scenario(result, description, log_dir, output_dir)\n"
            );
            assert_eq!(too_deep(&src), None, "{form:.60}");
            let done = std::thread::Builder::new()
                .stack_size(2 << 20)
                .spawn(move || crate::translate(&src, "p.txt").is_ok())
                .expect("thread")
                .join();
            assert!(done.is_ok(), "{form:.60}");
        }
    }
}
