//! Embeds the scenario library (`rules/library/*.dl`) into the crate as in-context examples:
//! writes `$OUT_DIR/library.rs`, a sorted list of `(file name, include_str!(path))`.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};

fn main() {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let dir = manifest.join("..").join("rules").join("library");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut files: Vec<PathBuf> = match fs::read_dir(&dir) {
        Ok(entries) => entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "dl"))
            .collect(),
        // No library next to the crate (e.g. a packaged build): embed none; the runtime
        // directory still works.
        Err(_) => Vec::new(),
    };
    files.sort();
    let mut out = String::from("/// The scenario library as embedded at build time.\npub(crate) const EMBEDDED: &[(&str, &str)] = &[\n");
    for f in &files {
        println!("cargo:rerun-if-changed={}", f.display());
        let name = f
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let abs = fs::canonicalize(f).unwrap_or_else(|_| f.clone());
        out.push_str(&format!(
            "    ({name:?}, include_str!({:?})),\n",
            path_str(&abs)
        ));
    }
    out.push_str("];\n");
    let out_dir = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_default());
    if let Err(e) = fs::write(out_dir.join("library.rs"), out) {
        panic!("writing the embedded library list: {e}");
    }
}

fn path_str(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}
