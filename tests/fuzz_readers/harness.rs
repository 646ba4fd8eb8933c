//! Running a reader over many mutants: in a child process (the test binary re-run on one test,
//! with its address space capped) so that an abort or a runaway allocation is seen as the child's
//! death, and inside it each mutant under `catch_unwind`, with every panic counted, even one a
//! reader catches itself.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Set in the child's environment to the name of the test it runs.
const CHILD_ENV: &str = "SCENALOG_FUZZ_CHILD";
/// The child's address-space cap in KiB (`ulimit -v`): 4 GiB. The inputs are a few kilobytes,
/// so a reader that validates sizes first never comes near it; one that trusts a declared size
/// fails to allocate and aborts, which the parent reports.
const ADDRESS_SPACE_KIB: u64 = 4 * 1024 * 1024;

/// Panics seen by the hook, caught or not.
static PANICS: AtomicUsize = AtomicUsize::new(0);

/// What the reader made of one mutant.
pub enum Outcome {
    /// Read (the mutation did not matter to it, or gave other valid content).
    Accepted,
    /// Rejected with this message.
    Rejected(String),
}

/// One fuzzing run: which test, what to mutate and how many times.
pub struct Campaign<'a> {
    /// The name of the `#[test]` function running it (the child re-runs exactly that test).
    pub test: &'a str,
    /// The valid input to mutate.
    pub base: &'a [u8],
    /// The mutants' seed.
    pub seed: u64,
    /// How many mutants.
    pub cases: u64,
    /// What every rejection's message must contain (the file's name).
    pub must_name: &'a str,
}

/// Runs the campaign's mutants through `read` in a child process and checks: the child ends
/// normally, no mutant panicked (even inside a reader that catches it), every rejection's
/// message names the file, and some mutants were rejected. Prints the counts (rejected /
/// accepted / panicked).
pub fn fuzz(c: &Campaign, read: impl Fn(&[u8]) -> Outcome) {
    let Campaign { test, seed, .. } = *c;
    if std::env::var(CHILD_ENV).as_deref() == Ok(test) {
        run_mutants(c, read);
        return;
    }
    let exe = std::env::current_exe().expect("the test binary's path");
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            // `;`, not `&&`: where the hard limit is already lower, that lower limit stays.
            "ulimit -v {ADDRESS_SPACE_KIB} 2>/dev/null; exec \"$0\" \"$@\""
        ))
        .arg(exe)
        .args([test, "--exact", "--nocapture", "--test-threads=1"])
        .env(CHILD_ENV, test)
        .output()
        .expect("run the child");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let last = stdout
        .lines()
        .rev()
        .find(|l| l.starts_with("mutant "))
        .unwrap_or("no mutant started");
    let summary = stdout
        .lines()
        .find(|l| l.starts_with("fuzz "))
        .map(str::to_owned);
    let tail: String = stderr
        .lines()
        .rev()
        .take(30)
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect::<Vec<_>>()
        .join("\n");
    assert!(
        out.status.success() && summary.is_some(),
        "{test}: the child ended with {} at or after `{last}` (seed {seed:#x}); its stderr ends:\n{tail}",
        out.status
    );
    if let Some(s) = summary {
        println!("{s}");
    }
}

/// The child's side: every mutant in process, each under `catch_unwind`.
fn run_mutants(c: &Campaign, read: impl Fn(&[u8]) -> Outcome) {
    let Campaign {
        test,
        base,
        seed,
        cases,
        must_name,
    } = *c;
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        PANICS.fetch_add(1, Ordering::SeqCst);
        default_hook(info);
    }));
    assert!(
        matches!(read(base), Outcome::Accepted),
        "{test}: the unmutated input must be read"
    );
    let (mut rejected, mut accepted) = (0u64, 0u64);
    let mut panicked = Vec::new();
    let mut unnamed = Vec::new();
    for i in 0..cases {
        let bytes = super::mutate::mutant(base, seed, i);
        println!("mutant {i}");
        let before = PANICS.load(Ordering::SeqCst) + scenalog_input::arrow::guarded_panics();
        match catch_unwind(AssertUnwindSafe(|| read(&bytes))) {
            Ok(Outcome::Accepted) => accepted += 1,
            Ok(Outcome::Rejected(message)) => {
                rejected += 1;
                if !message.contains(must_name) {
                    unnamed.push(format!("mutant {i}: {message}"));
                }
            }
            Err(_) => {}
        }
        // A panic the Arrow guard turned into an error counts too (its hook keeps it silent).
        if PANICS.load(Ordering::SeqCst) + scenalog_input::arrow::guarded_panics() != before {
            panicked.push(i);
        }
    }
    println!(
        "fuzz {test}: {cases} mutants of {} bytes (seed {seed:#x}): {rejected} rejected, {accepted} accepted, {} panicked",
        base.len(),
        panicked.len()
    );
    assert!(
        panicked.is_empty(),
        "{test}: mutants {panicked:?} panicked (seed {seed:#x})"
    );
    assert!(
        unnamed.is_empty(),
        "{test}: errors not naming {must_name}:\n{}",
        unnamed.join("\n")
    );
    assert!(rejected > 0, "{test}: no mutant was rejected");
}
