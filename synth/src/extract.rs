//! Taking the program out of a model's answer, and giving it the description comment.

/// What an answer held.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Extracted {
    /// Program text (from a fenced code block, or the whole answer when it reads as code).
    Program(String),
    /// No program: prose only, or an empty answer.
    NoCode,
}

/// The program in an answer: the last fenced code block that holds a clause (`:-`) or a
/// `referred` atom, else the last non-empty fenced block, else the whole answer when it has a
/// clause (`:-`). `<think>…</think>` sections of reasoning models are dropped first (and
/// everything before a lone `</think>`). An answer cut off inside a block still yields the
/// block's text.
pub fn extract(answer: &str) -> Extracted {
    let answer = strip_think(answer);
    let blocks = fenced_blocks(&answer);
    let looks_like_code = |b: &str| b.contains(":-") || b.contains("referred");
    if let Some(b) = blocks.iter().rev().find(|b| looks_like_code(b)) {
        return Extracted::Program(b.clone());
    }
    if let Some(b) = blocks.iter().rev().find(|b| !b.trim().is_empty()) {
        return Extracted::Program(b.clone());
    }
    if blocks.is_empty() && answer.contains(":-") {
        return Extracted::Program(answer.trim().to_string());
    }
    Extracted::NoCode
}

fn strip_think(answer: &str) -> String {
    let mut out = String::new();
    let mut rest = answer;
    while let Some(i) = rest.find("<think>") {
        out.push_str(&rest[..i]);
        match rest[i..].find("</think>") {
            Some(j) => rest = &rest[i + j + "</think>".len()..],
            // Thinking never ended: nothing after it is an answer.
            None => return out,
        }
    }
    out.push_str(rest);
    // A template that opens the thinking itself leaves only the closing tag in the answer.
    match out.rfind("</think>") {
        Some(i) => out[i + "</think>".len()..].to_string(),
        None => out,
    }
}

/// The contents of every fenced block (``` or ~~~), in order; a block left open at the end runs
/// to the end of the answer.
fn fenced_blocks(text: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<(String, String)> = None; // (fence, body)
    for line in text.lines() {
        let t = line.trim_start();
        match &mut current {
            None => {
                if let Some(fence) = fence_of(t) {
                    current = Some((fence, String::new()));
                }
            }
            Some((fence, body)) => {
                let closing = t.trim_end();
                if closing.starts_with(fence.as_str())
                    && closing.chars().all(|c| fence.starts_with(c))
                {
                    blocks.push(std::mem::take(body));
                    current = None;
                } else {
                    body.push_str(line);
                    body.push('\n');
                }
            }
        }
    }
    if let Some((_, body)) = current {
        blocks.push(body);
    }
    blocks
}

/// The fence a line opens (three or more backticks or tildes), if it opens one.
fn fence_of(line: &str) -> Option<String> {
    let c = line.chars().next().filter(|&c| c == '`' || c == '~')?;
    let n = line.chars().take_while(|&x| x == c).count();
    (n >= 3).then(|| c.to_string().repeat(n))
}

/// The program with `// description: <description>` as its first line: any description comment
/// the model wrote is dropped, trailing whitespace trimmed, one final newline.
pub fn with_description(program: &str, description: &str) -> String {
    let mut out = format!("// description: {}\n", one_line(description));
    let mut started = false;
    for line in program.lines() {
        let t = line.trim();
        let is_desc = t
            .strip_prefix("//")
            .is_some_and(|r| r.trim_start().starts_with("description:"));
        if is_desc || (!started && t.is_empty()) {
            continue;
        }
        started = true;
        out.push_str(line.trim_end());
        out.push('\n');
    }
    while out.ends_with("\n\n") {
        out.pop();
    }
    out
}

/// A description on one line: whitespace runs (newlines included) become one space.
pub fn one_line(description: &str) -> String {
    description.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn last_code_block_wins() {
        let a = "First try:\n```\nreferred(X, T) :- a(X, T).\n```\nBetter:\n```scenalog\nreferred(X, T) :- b(X, T).\n```\nDone.";
        assert_eq!(
            extract(a),
            Extracted::Program("referred(X, T) :- b(X, T).\n".into())
        );
    }

    #[test]
    fn a_trailing_output_block_is_not_the_program() {
        let a = "```prolog\nreferred(X, T) :- b(X, T).\n```\nOutput:\n```\n(none)\n```";
        assert_eq!(
            extract(a),
            Extracted::Program("referred(X, T) :- b(X, T).\n".into())
        );
    }

    #[test]
    fn whole_answer_when_unfenced_code() {
        let a = "referred(X, T) :- ego(X), present(X, T).";
        assert_eq!(extract(a), Extracted::Program(a.into()));
    }

    #[test]
    fn prose_and_empty_answers_have_no_code() {
        assert_eq!(
            extract("I cannot write that program, sorry."),
            Extracted::NoCode
        );
        assert_eq!(extract(""), Extracted::NoCode);
        assert_eq!(extract("```\n\n```"), Extracted::NoCode);
    }

    #[test]
    fn think_sections_and_open_blocks() {
        let a = "<think>maybe ```x :- y.``` </think>\n~~~~\nreferred(X, T) :- c(X, T).\n";
        assert_eq!(
            extract(a),
            Extracted::Program("referred(X, T) :- c(X, T).\n".into())
        );
        assert_eq!(extract("<think>referred(X,T) :- a."), Extracted::NoCode);
        assert_eq!(
            extract("referred(X, T) :- a(X, T).\n</think>\nNo program."),
            Extracted::NoCode
        );
        // A longer fence is not closed by a shorter one.
        let a = "````\nx :- y.\n```\nz :- w.\n````\n";
        assert_eq!(
            extract(a),
            Extracted::Program("x :- y.\n```\nz :- w.\n".into())
        );
    }

    #[test]
    fn description_comment_first_and_only_once() {
        let p =
            "\n// description: something else\nreferred(X, T) :- ego(X), present(X, T).   \n\n\n";
        assert_eq!(
            with_description(p, "the\nego  car"),
            "// description: the ego car\nreferred(X, T) :- ego(X), present(X, T).\n"
        );
    }
}
