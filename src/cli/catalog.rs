//! `scenalog catalog [NAME]`: print the catalog of relations and the prelude's concepts, or one
//! relation of either.

use std::process::ExitCode;

use crate::api::catalog::catalog;

/// Arguments of `scenalog catalog`.
#[derive(clap::Args)]
pub struct Args {
    /// Print only this relation (e.g. `near`); exit 2 if the catalog has no such relation.
    pub name: Option<String>,
    /// Print JSON (an array of relation objects, or one object with NAME) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Prints the catalog (or one relation) as text or JSON; exit 2 for a name neither the catalog
/// nor the prelude has.
pub fn run(args: Args) -> ExitCode {
    let listing = match catalog(args.name.as_deref()) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("scenalog catalog: {}", e.flags());
            return ExitCode::from(2);
        }
    };
    if args.json {
        outln!("{:#}", listing.json());
    } else {
        out!("{}", listing.text());
    }
    ExitCode::SUCCESS
}
