//! `scenalog catalog [NAME]`: print the catalog of relations, or one relation of it.

use std::process::ExitCode;

use scenalog_facts::catalog;

/// Arguments of `scenalog catalog`.
#[derive(clap::Args)]
pub struct Args {
    /// Print only this relation (e.g. `near`); exit 2 if the catalog has no such relation.
    pub name: Option<String>,
    /// Print JSON (an array of relation objects, or one object with NAME) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Prints the catalog (or one relation) as text or JSON.
pub fn run(args: Args) -> ExitCode {
    match args.name {
        None if args.json => outln!("{:#}", catalog::render_json()),
        None => out!("{}", catalog::render_text()),
        Some(name) => {
            let Some(r) = catalog::relation(&name) else {
                let names: Vec<&str> = catalog::catalog().iter().map(|r| r.name).collect();
                eprintln!(
                    "scenalog catalog: no relation `{name}` in the catalog; it has: {}",
                    names.join(", ")
                );
                return ExitCode::from(2);
            };
            if args.json {
                outln!("{:#}", r.to_json());
            } else {
                outln!("{r}\n    {}", r.doc);
                for c in r.columns {
                    let values = if c.values.is_empty() {
                        String::new()
                    } else {
                        let v: Vec<String> = c.values.iter().map(|v| format!("{v:?}")).collect();
                        format!(", one of {}", v.join(", "))
                    };
                    outln!("    {}: {}{values}", c.name, c.ty);
                }
            }
        }
    }
    ExitCode::SUCCESS
}
