//! The default limits of a mining run: the tuple budget of one (log, program) pair, sized to the
//! machine's memory and the number of pairs evaluated at once, and the per-pair time limit.

use std::time::Duration;

/// What one tuple costs at the peak of a pair, in bytes, all copies together: the extracted
/// columns, the engine's packed rows (and their sorted merges) and the decoded result.
pub const BYTES_PER_TUPLE: u64 = 256;

/// The budget when the machine's memory cannot be read.
pub const FALLBACK_MAX_TUPLES: usize = 20_000_000;

/// The smallest and largest default budget.
pub const MAX_TUPLES_RANGE: (usize, usize) = (1_000_000, 100_000_000);

/// The default per-pair time limit of `mine`: long past what any library program takes on a
/// log (well under a second each), short enough that a runaway program cannot stall a run.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_secs(120);

/// The machine's physical memory in bytes (`MemTotal` of `/proc/meminfo`), when readable.
pub fn machine_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_mem_total(&text)
}

/// `MemTotal:  N kB` → bytes.
fn parse_mem_total(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let mut words = line.split_whitespace().skip(1);
    let n: u64 = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") => n.checked_mul(1024),
        _ => None,
    }
}

/// The default tuple budget of one pair when `threads` pairs run at once: half the machine's
/// memory shared by the threads, at [`BYTES_PER_TUPLE`] each, within [`MAX_TUPLES_RANGE`].
pub fn default_max_tuples(memory: Option<u64>, threads: usize) -> usize {
    let Some(memory) = memory else {
        return FALLBACK_MAX_TUPLES;
    };
    let per_pair = memory / 2 / threads.max(1) as u64 / BYTES_PER_TUPLE;
    let (lo, hi) = MAX_TUPLES_RANGE;
    usize::try_from(per_pair).unwrap_or(hi).clamp(lo, hi)
}

/// The engine's limits for one (log, program) pair: `max_tuples` (default
/// [`default_max_tuples`] of this machine with `threads` pairs at once) and `timeout_ms`
/// (default [`DEFAULT_TIMEOUT`]). Every command that evaluates programs on logs uses these, so
/// none of them can hang on a runaway program or fill the memory.
pub fn pair_limits(
    max_tuples: Option<u64>,
    timeout_ms: Option<u64>,
    threads: usize,
) -> scenalog_engine::Options {
    scenalog_engine::Options {
        max_tuples: max_tuples.map_or_else(
            || default_max_tuples(machine_memory(), threads),
            |n| usize::try_from(n).unwrap_or(usize::MAX),
        ),
        timeout: Some(timeout_ms.map_or(DEFAULT_TIMEOUT, Duration::from_millis)),
        ..scenalog_engine::Options::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mem_total_is_read_in_bytes() {
        let text = "MemTotal:       24576000 kB\nMemFree:         1000 kB\n";
        assert_eq!(parse_mem_total(text), Some(24_576_000 * 1024));
        assert_eq!(parse_mem_total("MemTotal: lots\n"), None);
        assert_eq!(parse_mem_total("MemTotal: 12 MB\n"), None);
        assert_eq!(parse_mem_total(""), None);
    }

    #[test]
    fn the_budget_shares_half_the_memory_between_threads() {
        let gib = 1024 * 1024 * 1024;
        // 24 GiB, 2 threads: 6 GiB a pair, 25,165,824 tuples of 256 bytes.
        assert_eq!(default_max_tuples(Some(24 * gib), 2), 25_165_824);
        assert_eq!(default_max_tuples(Some(24 * gib), 4), 12_582_912);
        // Clamped at both ends; unknown memory gets the fallback.
        assert_eq!(default_max_tuples(Some(gib), 64), MAX_TUPLES_RANGE.0);
        assert_eq!(default_max_tuples(Some(1 << 50), 1), MAX_TUPLES_RANGE.1);
        assert_eq!(default_max_tuples(None, 2), FALLBACK_MAX_TUPLES);
    }
}
