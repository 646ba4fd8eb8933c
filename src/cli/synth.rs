//! `scenalog synth`: write a rule program from a description with an LLM, repairing it on the
//! checker's diagnostics.
//!
//! One description: prints the program (or writes it with `-o`); exit 0 when it checks clean,
//! 1 when the rounds ran out (the last attempt is still printed or written, with its diagnostics
//! in `FILE.dl.diagnostics.json`), 2 when the LLM could not be reached or an input is unusable.
//! Many: `--descriptions FILE.txt --out DIR` writes one `.dl` per description and a summary;
//! exit 0 when all are clean, 1 when some failed, 2 when the server could not be reached.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use crate::api::inputs::SAMPLE_LOGS;
use crate::api::synth::{
    self as api, BatchRequest, EvalRequest, ItemStatus, OneRequest, Outcome, Price, SynthConfig,
    SynthSettings, Synthesizer, ENV_API_KEY, ENV_BASE_URL, ENV_MODEL,
};
use crate::api::{Limits, Names};

/// Arguments of `scenalog synth` (boxed: they are many, and the command enum stays small).
#[derive(clap::Args)]
pub struct Args {
    /// The options.
    #[command(flatten)]
    pub options: Box<Options>,
}

/// The options of `scenalog synth`.
#[derive(clap::Args)]
pub struct Options {
    /// The scenario description, e.g. "vehicle making a left turn".
    #[arg(
        required_unless_present_any = ["descriptions", "eval", "print_grammar"],
        conflicts_with_all = ["descriptions", "eval"]
    )]
    pub description: Option<String>,
    /// Measure synthesis on a file of descriptions (one a line): held-out prompts, each clean
    /// program run on the sample logs (`--logs`), a report on standard output.
    #[arg(long, value_name = "FILE.txt", conflicts_with_all = ["descriptions", "output"])]
    pub eval: Option<PathBuf>,
    /// The sample logs `--eval` runs programs on (each subdirectory one AV2 log).
    #[arg(long, value_name = "DIR", default_value = "tests/data/av2/logs")]
    pub logs: PathBuf,
    /// The ground truth `--eval` scores the descriptions that are its prompts against (their
    /// programs mined on `--logs`, as `scenalog mine` scores them) [default: the bundled
    /// fixture's, tests/data/av2/eval/combined_gt_dev.pkl, when present].
    #[arg(long, value_name = "G", requires = "eval")]
    pub gt: Option<PathBuf>,
    /// With `--eval`: print the report as one JSON object instead of text.
    #[arg(long, requires = "eval")]
    pub json: bool,
    /// Prices per million tokens, `IN,CACHED,OUT` (uncached input, cached input, output), e.g.
    /// `2,0.5,8`: the cost of the tokens the server reports is shown with them.
    #[arg(long, value_name = "IN,CACHED,OUT", value_parser = Price::parse)]
    pub price: Option<Price>,
    /// With `--eval`: most tuples one (log, program) evaluation may hold, as `mine
    /// --max-tuples` [default: sized to the machine, as `mine`'s].
    #[arg(long, value_name = "N", requires = "eval", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_tuples: Option<u64>,
    /// With `--eval`: longest one (log, program) evaluation may take, in milliseconds; a program
    /// past it is reported as an error for its description [default: 120000, as `mine`'s].
    #[arg(long, value_name = "MS", requires = "eval", value_parser = clap::value_parser!(u64).range(1..))]
    pub timeout_ms: Option<u64>,
    /// Held-out prompts: leave out the description's own library program and its near-duplicates
    /// (always on with `--eval`).
    #[arg(long)]
    pub held_out: bool,
    /// A file of descriptions, one a line (blank lines and `#` comments skipped); needs `--out`.
    #[arg(long, value_name = "FILE.txt", requires = "out")]
    pub descriptions: Option<PathBuf>,
    /// Directory for the programs of `--descriptions` (one `<slug>.dl` each, with transcripts).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write the program to this file instead of standard output (with its transcript beside it).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "FILE.dl",
        conflicts_with = "descriptions"
    )]
    pub output: Option<PathBuf>,
    /// Print the prompt the description would be sent with, and ask nothing.
    #[arg(long)]
    pub print_prompt: bool,
    /// Print the grammar (GBNF) `--grammar` sends, and ask nothing.
    #[arg(long)]
    pub print_grammar: bool,
    /// Descriptions synthesized at once with `--descriptions`.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub jobs: u32,
    /// Also write the transcript of every round (JSON) to this file (one description).
    #[arg(long, value_name = "FILE.json", conflicts_with = "descriptions")]
    pub transcript: Option<PathBuf>,
    /// The server, the cache and the prompt.
    #[command(flatten)]
    pub synth: SynthArgs,
}

/// The options that make a [`SynthConfig`]: the server, the cache, the rounds and the examples.
/// `scenalog mine --descriptions` flattens these too.
#[derive(clap::Args, Clone, Debug)]
pub struct SynthArgs {
    /// Cache completions here (default: DIR/.llm-cache with `--out`, none otherwise).
    #[arg(long, value_name = "DIR")]
    pub cache_dir: Option<PathBuf>,
    /// Completions to ask for at most: the first attempt and the repairs.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=20))]
    pub rounds: u32,
    /// Base URL of an OpenAI-compatible server [env: SCENALOG_LLM_BASE_URL; default:
    /// http://127.0.0.1:8080/v1, llama.cpp's server].
    #[arg(long, value_name = "URL")]
    pub base_url: Option<String>,
    /// Model name [env: SCENALOG_LLM_MODEL; default: "default"].
    #[arg(long)]
    pub model: Option<String>,
    /// API key, sent as a bearer token [env: SCENALOG_LLM_API_KEY].
    #[arg(long, value_name = "KEY")]
    pub api_key: Option<String>,
    /// Sampling temperature, or "default" to send none (for models that accept only their own).
    #[arg(long, default_value = "0", value_name = "T|default")]
    pub temperature: String,
    /// Seconds one completion may take before it is retried.
    #[arg(long, default_value_t = 300, value_name = "SECS")]
    pub timeout: u64,
    /// Retries after a failed attempt (refused connection, timeout, 429, 5xx).
    #[arg(long, default_value_t = 4)]
    pub retries: u32,
    /// In-context examples per prompt: the most similar of the library ("all" for every one).
    #[arg(long, default_value = "8", value_name = "K|all")]
    pub examples: String,
    /// Read the example library from this directory instead of the one built in.
    #[arg(long, value_name = "DIR")]
    pub library: Option<PathBuf>,
    /// Candidate programs per description (1 to 32): the first asked as with one, the others
    /// sampled at temperature 0.7; each clean one is run on the logs (`--logs`, the sample logs by
    /// default) and the one whose matches agree most with the others' is kept.
    #[arg(long, default_value_t = 1, value_name = "K", value_parser = clap::value_parser!(u32).range(1..=32))]
    pub candidates: u32,
    /// Stop asking the server once this many tokens (prompt and completion, as it reports them)
    /// are spent; what was not synthesized is reported, and cached answers cost nothing.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_tokens: Option<u64>,
    /// Evidence rounds (0 to 5): the kept program is run on the logs and the model is told what
    /// it matches (tracks and frames per category, the longest match's proof, or the nearest
    /// misses), then keeps it or revises it [default: 1 with --candidates above 1, else 0].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=5))]
    pub evidence_rounds: Option<u32>,
    /// Send the language's grammar (GBNF) so an answer cannot fail to parse, in the field this
    /// server reads: `llama-cpp` (`grammar`), `vllm` (`structured_outputs.grammar`) or
    /// `sglang` (`ebnf`). `scenalog synth --print-grammar` prints it.
    #[arg(long, value_name = "SERVER")]
    pub grammar: Option<GrammarServer>,
}

/// The servers whose grammar field `--grammar` knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum GrammarServer {
    /// llama.cpp's server: the `grammar` field.
    LlamaCpp,
    /// vLLM: `structured_outputs: {"grammar": …}`.
    Vllm,
    /// SGLang: the `ebnf` field.
    Sglang,
}

impl GrammarServer {
    fn field(self) -> crate::api::synth::GrammarField {
        match self {
            GrammarServer::LlamaCpp => crate::api::synth::GrammarField::LlamaCpp,
            GrammarServer::Vllm => crate::api::synth::GrammarField::Vllm,
            GrammarServer::Sglang => crate::api::synth::GrammarField::Sglang,
        }
    }
}

fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("scenalog synth: {message}");
    ExitCode::from(2)
}

/// The settings of the flags: `--temperature` a number from 0 to 2 or "default", `--examples` a
/// number or "all".
fn settings(args: &SynthArgs, match_logs: &[PathBuf]) -> Result<SynthSettings, String> {
    let temperature = match args.temperature.trim() {
        "default" => None,
        t => Some(
            t.parse::<f64>()
                .ok()
                .filter(|t| (0.0..=2.0).contains(t))
                .ok_or_else(|| {
                    format!(
                        "--temperature: expected a number from 0 to 2 or \"default\", got {t:?}"
                    )
                })?,
        ),
    };
    let examples = match args.examples.trim() {
        "all" => None,
        k => Some(
            k.parse::<usize>()
                .map_err(|_| format!("--examples: expected a number or \"all\", got {k:?}"))?,
        ),
    };
    Ok(SynthSettings {
        cache_dir: args.cache_dir.clone(),
        rounds: args.rounds as usize,
        base_url: args.base_url.clone(),
        model: args.model.clone(),
        api_key: args.api_key.clone(),
        temperature,
        timeout: Duration::from_secs(args.timeout),
        retries: args.retries,
        examples,
        library: args.library.clone(),
        held_out: false,
        candidates: args.candidates as usize,
        match_logs: match_logs.to_vec(),
        match_limits: Limits::default(),
        max_tokens: args.max_tokens,
        evidence_rounds: args.evidence_rounds.map(|n| n as usize),
        grammar: args.grammar.map(GrammarServer::field),
    })
}

/// The synthesis configuration from the flags and the environment; completions are cached in
/// `--cache-dir`, else in `default_cache` (e.g. `OUT/.llm-cache`), else not at all. Warns on
/// stderr about library examples left out because they do not check clean.
pub fn synth_config(
    args: &SynthArgs,
    default_cache: Option<PathBuf>,
    match_logs: &[PathBuf],
) -> Result<SynthConfig, String> {
    let configured =
        api::config(&settings(args, match_logs)?, default_cache).map_err(|e| e.flags())?;
    if !configured.left_out.is_empty() {
        eprintln!(
            "scenalog synth: warning: examples left out because they do not check clean: {}",
            configured.left_out.join(", ")
        );
    }
    Ok(configured.config)
}

/// Runs the subcommand.
pub fn run(args: Args) -> ExitCode {
    let args = *args.options;
    if args.print_grammar {
        out!("{}", api::grammar());
        return ExitCode::SUCCESS;
    }
    let default_cache = args.out.as_ref().map(|d| d.join(".llm-cache"));
    // `--logs` left at its default outside the repository: the bundled sample logs.
    let match_logs = if args.logs == std::path::Path::new(SAMPLE_LOGS) && !args.logs.is_dir() {
        Vec::new()
    } else {
        vec![args.logs.clone()]
    };
    let mut config = match synth_config(&args.synth, default_cache, &match_logs) {
        Ok(c) => c,
        Err(e) => return fail(e),
    };
    config.held_out = args.held_out || args.eval.is_some();
    let synth = match api::synthesizer(config) {
        Ok(s) => s,
        Err(e) => return fail(e.flags()),
    };
    if args.print_prompt {
        let Some(description) = &args.description else {
            return fail("--print-prompt needs a description");
        };
        out!("{}", api::prompt_text(&synth, description));
        return ExitCode::SUCCESS;
    }
    if let Some(file) = &args.eval {
        let request = EvalRequest {
            descriptions: file.clone(),
            logs: args.logs.clone(),
            gt: args.gt.clone(),
            limits: Limits {
                max_tuples: args.max_tuples,
                timeout_ms: args.timeout_ms,
            },
            price: args.price,
            names: Names::Flags,
        };
        return eval(&synth, &request, args.json);
    }
    match (&args.description, &args.descriptions, &args.out) {
        (Some(d), _, _) => one(&synth, d, &args),
        (None, Some(file), Some(out)) => {
            many(&synth, file, out, args.jobs as usize, args.price.as_ref())
        }
        _ => fail("give a description, or --descriptions FILE.txt with --out DIR"),
    }
}

/// `--eval FILE`: the report on stdout (JSON with `--json`). Exit 0 when it ran, 1 when the
/// fixture scoring failed (the rest is reported), 2 when an input is unusable or the server could not be reached for a
/// description.
fn eval(synth: &Synthesizer, request: &EvalRequest, json: bool) -> ExitCode {
    let evaluated = match api::evaluate(synth, request) {
        Ok(e) => e,
        Err(e) => return fail(e.flags()),
    };
    let mut code = ExitCode::SUCCESS;
    if let Some(e) = &evaluated.fixture_error {
        eprintln!("scenalog synth: the fixture score: {}", e.flags());
        code = ExitCode::from(1);
    }
    if json {
        match serde_json::to_string_pretty(&evaluated.report.to_json()) {
            Ok(text) => outln!("{text}"),
            Err(e) => return fail(format!("cannot encode the report: {e}")),
        }
    } else {
        out!("{}", evaluated.report.render());
    }
    // A server that could not be reached leaves the report without programs: not a success.
    let report = &evaluated.report;
    let unreachable = report.unreachable();
    if unreachable > 0 {
        let first = report
            .items
            .iter()
            .find(|i| i.unreachable)
            .and_then(|i| i.error.as_deref())
            .unwrap_or_default();
        eprintln!(
            "scenalog synth: the LLM server could not be reached for {unreachable} of {} descriptions: {first}",
            report.items.len()
        );
        return ExitCode::from(2);
    }
    code
}

fn one(synth: &Synthesizer, description: &str, args: &Options) -> ExitCode {
    let request = OneRequest {
        description: description.to_string(),
        output: args.output.clone(),
        transcript: args.transcript.clone(),
    };
    let done = match api::synthesize_one(synth, &request) {
        Ok(d) => d,
        Err(e) => return fail(e.flags()),
    };
    let t = &done.transcript;
    if let Some(e) = &done.transcript_error {
        eprintln!("scenalog synth: {e}");
    }
    if let Some(e) = &done.output_error {
        // Keep the answer: print it rather than lose it.
        if let Some(p) = t.program() {
            out!("{p}");
        }
        return fail(e);
    }
    if args.output.is_none() {
        if let Some(p) = t.program() {
            out!("{p}");
        }
    }
    let rounds = t.rounds.len();
    eprintln!(
        "scenalog synth: {}",
        api::tokens_line(&t.usage(), args.price.as_ref())
    );
    match &t.outcome {
        Outcome::Clean { round } => {
            eprintln!("scenalog synth: checked clean in round {round}");
            if let Some(search) = &t.search {
                eprintln!(
                    "scenalog synth: {} candidates: {}",
                    search.candidates.len(),
                    search.reason
                );
                for c in &search.candidates {
                    let matched = match (&c.matched, &c.match_error) {
                        (Some(n), _) => format!("matched {n} boxes"),
                        (None, Some(e)) => format!("could not run ({e})"),
                        (None, None) => "not clean".to_string(),
                    };
                    let agreement = c
                        .agreement
                        .map(|a| format!(", agreement {a:.3}"))
                        .unwrap_or_default();
                    eprintln!(
                        "scenalog synth:   candidate {}: {matched}{agreement}; {}",
                        c.sample,
                        api::tokens_line(&c.transcript.usage(), args.price.as_ref())
                    );
                }
            }
            for round in &t.evidence {
                eprintln!("scenalog synth: {}", round.summary());
            }
            ExitCode::SUCCESS
        }
        Outcome::Failed => {
            eprintln!(
                "scenalog synth: no clean program after {rounds} round{}",
                if rounds == 1 { "" } else { "s" }
            );
            report_last(&done, args.output.as_deref());
            ExitCode::from(1)
        }
        Outcome::Unreachable { error } => {
            report_last(&done, args.output.as_deref());
            eprintln!("scenalog synth: {error}");
            eprintln!(
                "scenalog synth: set the server with --base-url or {ENV_BASE_URL} (and {ENV_MODEL}, {ENV_API_KEY})"
            );
            ExitCode::from(2)
        }
        Outcome::OverBudget { error } => {
            report_last(&done, args.output.as_deref());
            eprintln!("scenalog synth: {error}");
            ExitCode::from(2)
        }
    }
}

/// Says where the last attempt and its diagnostics are (with `-o`), or prints the diagnostics.
fn report_last(done: &api::OneOutcome, output: Option<&std::path::Path>) {
    if done.transcript.program().is_none() {
        return;
    }
    match (output, &done.diagnostics_file) {
        (Some(path), Some(diagnostics)) => eprintln!(
            "scenalog synth: the last attempt is in {}, its diagnostics in {}",
            path.display(),
            diagnostics.display()
        ),
        _ => {
            let color = std::io::stderr().is_terminal();
            if let Some(text) = done.diagnostics_text(color) {
                eprint!("{text}");
            }
        }
    }
}

fn many(
    synth: &Synthesizer,
    file: &std::path::Path,
    out: &std::path::Path,
    jobs: usize,
    price: Option<&Price>,
) -> ExitCode {
    let request = BatchRequest {
        descriptions: file.to_path_buf(),
        out: out.to_path_buf(),
        jobs,
        progress: true,
    };
    // The folder stays held until the report is printed.
    let done = match api::synthesize_batch(synth, &request) {
        Ok(d) => d,
        Err(e) => return fail(e.flags()),
    };
    let report = &done.report;
    for item in &report.items {
        let status = match &item.status {
            ItemStatus::Resumed => "already clean".to_string(),
            ItemStatus::Clean { round } => format!("clean in round {round}"),
            ItemStatus::Failed => "FAILED".to_string(),
            ItemStatus::Unreachable { error } => format!("UNREACHABLE: {error}"),
            ItemStatus::OverBudget { error } => format!("OVER BUDGET: {error}"),
            ItemStatus::Skipped => "not attempted".to_string(),
        };
        outln!("{}\t{status}\t{}", item.path.display(), item.description);
    }
    let s = &report.summary;
    eprintln!("scenalog synth: {s}");
    if let Some(p) = price {
        eprintln!("scenalog synth: cost {:.4}", p.cost(&s.usage));
    }
    if s.unreachable + s.skipped > 0 {
        ExitCode::from(2)
    } else if s.failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
