//! The integration tests of scenalog-facts in one binary (one link instead of one per file): a module
//! per concern, each saying what it tests. Run one with `cargo test -p scenalog-facts --test it MODULE::`.

mod bad_input;
mod real_logs;

/// The bundled sample log `id` (`tests/data/av2/logs/<id>`). The test kit crate
/// (`scenalog-testkit`) says the same for the crates above this one; it is built on this crate,
/// so this crate's tests keep their own line.
fn log_dir(id: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2/logs")
        .join(id)
}
