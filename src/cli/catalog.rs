//! `scenalog catalog`: print the catalog of relations.

use std::process::ExitCode;

use scenalog_facts::catalog;

/// Arguments of `scenalog catalog`.
#[derive(clap::Args)]
pub struct Args {
    /// Print the catalog as a JSON array instead of text.
    #[arg(long)]
    json: bool,
}

/// Prints the catalog as text or JSON.
pub fn run(args: Args) -> ExitCode {
    if args.json {
        println!("{:#}", catalog::render_json());
    } else {
        print!("{}", catalog::render_text());
    }
    ExitCode::SUCCESS
}
