//! `scenalog catalog [NAME]`: print the catalog of relations and the prelude's concepts, or one
//! relation of either.

use std::process::ExitCode;

use scenalog_facts::catalog;
use scenalog_rules::prelude;

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
        None if args.json => {
            let mut all = catalog::catalog()
                .iter()
                .map(|r| r.to_json())
                .collect::<Vec<_>>();
            all.extend(prelude::relations().iter().map(|r| r.to_json()));
            outln!("{:#}", serde_json::Value::Array(all))
        }
        None => {
            out!("{}", catalog::render_text());
            outln!(
                "\nConcepts (the prelude: relations every program can use without defining them)"
            );
            out!("{}", prelude::render_text());
        }
        Some(name) => {
            if let Some(p) = prelude::relation(&name) {
                if args.json {
                    outln!("{:#}", p.to_json());
                } else {
                    outln!("{} (prelude)\n    {}", p.signature(), p.doc);
                    for line in &p.definition {
                        outln!("    {line}");
                    }
                }
                return ExitCode::SUCCESS;
            }
            let Some(r) = catalog::relation(&name) else {
                let names: Vec<&str> = catalog::catalog()
                    .iter()
                    .map(|r| r.name)
                    .chain(prelude::relations().iter().map(|r| r.name.as_str()))
                    .collect();
                eprintln!(
                    "scenalog catalog: no relation `{name}` in the catalog or the prelude; they have: {}",
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
