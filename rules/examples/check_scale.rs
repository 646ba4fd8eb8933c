//! How `check` scales with the size of a program: parse, stratify and the whole check of
//! generated programs of 1,000, 10,000 and 100,000 items of four shapes: `rules` (a chain of
//! helpers, each its own stratum, as `benches/check.rs` builds them), `body` (one rule of that
//! many atoms), `bindings` (one rule binding that many variables, each from the next one written)
//! `unknown` (that many rules over unknown predicates: the error path with its hints) and
//! `nested` (`min` calls nested that deep, past the nesting limit: the parser's error path).
//! Wall-clock medians of `REPS` runs each, and the CPU time of the whole check per item (from
//! `/proc/self/stat`, over enough runs to pass 100,000 items, so a busy machine's waiting is left
//! out; Linux only, else "-").
//!
//! Run: `cargo run --release -p scenalog-rules --example check_scale [-- SHAPES… SIZES…]` (the
//! figures are in rules/README.md).

use std::time::{Duration, Instant};

use scenalog_rules::{check, parse, strata, CheckOptions};

/// Runs per size; the median is printed.
const REPS: usize = 3;

#[path = "support/chain.rs"]
mod chain;
use chain::{
    bindings_program, chain_program, nested_calls_program, unknown_program, wide_body_program,
};

fn median(f: impl Fn() -> Duration) -> Duration {
    let mut v: Vec<Duration> = (0..REPS).map(|_| f()).collect();
    v.sort_unstable();
    v[REPS / 2]
}

/// CPU seconds (user + system) this process has used, from `/proc/self/stat` (100 ticks a second).
fn cpu_secs() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which ends with the last ')'): utime is the 12th, stime the 13th.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn timed<T>(f: impl FnOnce() -> T) -> Duration {
    let t = Instant::now();
    std::hint::black_box(f());
    t.elapsed()
}

/// The program shapes measured: a name and how a program of `n` items is written.
/// A shape: its name and the program of `n` items.
type Shape = (&'static str, fn(usize) -> String);

const SHAPES: &[Shape] = &[
    ("rules", chain_program),
    ("body", wide_body_program),
    ("bindings", bindings_program),
    ("unknown", unknown_program),
    ("nested", nested_calls_program),
];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let sizes: Vec<usize> = {
        let given: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
        if given.is_empty() {
            vec![1_000, 10_000, 100_000]
        } else {
            given
        }
    };
    let shapes: Vec<&Shape> = SHAPES
        .iter()
        .filter(|(name, _)| {
            !args.iter().any(|a| SHAPES.iter().any(|s| s.0 == a)) || args.iter().any(|a| a == name)
        })
        .collect();
    println!(
        "shape | items | bytes | parse | stratify | parse + check (wall) | CPU µs per item (check)"
    );
    for (shape, make) in shapes {
        for &n in &sizes {
            let src = make(n);
            if *shape == "rules" {
                let out = check(&src, &CheckOptions::default());
                let strata_n = out.program.as_ref().map_or(0, |p| p.strata.len());
                if strata_n != n + 2 {
                    eprintln!(
                        "{n} rules: {strata_n} strata, {:?}",
                        out.diagnostics.first()
                    );
                    std::process::exit(1);
                }
            }
            let program = parse(&src).0;
            let parse_t = median(|| timed(|| parse(&src)));
            let strat_t = median(|| timed(|| strata::stratify(&program)));
            let check_t = median(|| timed(|| check(&src, &CheckOptions::default())));
            let runs = (100_000 / n).max(REPS);
            let cpu = cpu_secs().and_then(|before| {
                for _ in 0..runs {
                    std::hint::black_box(check(&src, &CheckOptions::default()));
                }
                Some((cpu_secs()? - before) * 1e6 / (runs * n) as f64)
            });
            let ms = |d: Duration| d.as_secs_f64() * 1e3;
            println!(
                "{shape} | {n} | {} | {:.1} ms | {:.1} ms | {:.1} ms | {}",
                src.len(),
                ms(parse_t),
                ms(strat_t),
                ms(check_t),
                cpu.map_or("-".to_string(), |c| format!("{c:.2}"))
            );
        }
    }
}
