//! Writing programs from descriptions with an LLM (`scenalog synth`, and `mine --descriptions`,
//! `mine --log-prompts --synthesize`): the configuration from plain settings ([`config`]), one
//! description ([`synthesize_one`]), a file of them into a directory ([`synthesize_batch`], the
//! folder held while it is written), the measurement of a description set on the sample logs
//! ([`evaluate`], with the fixture score), and the programs a run mines ([`synthesize`]).
//!
//! The synthesis crate's result types come through here ([`Transcript`], [`BatchReport`],
//! [`EvalReport`], …): a front end prints them, it does not call the crate.

use std::path::{Path, PathBuf};
use std::time::Duration;

use scenalog_synth::batch::{self, write_outputs};
use scenalog_synth::{library, prompt, BatchOptions, LlmConfig};

use crate::api::error::{invalid, Error, ErrorKind, Field, Message, Names};
use crate::api::inputs::{bundled, SAMPLE_GT};
use crate::api::limits::Limits;
use crate::pipeline::lock::OutputLock;

pub use scenalog_synth::client::{ENV_API_KEY, ENV_BASE_URL, ENV_MODEL};
pub use scenalog_synth::evaluation::EvalReport;
pub use scenalog_synth::{
    BatchReport, ItemStatus, Outcome, Price, SynthConfig, Synthesizer, Transcript, Usage,
};

/// How to synthesize programs with the LLM, for a run that mines them.
pub struct Synthesis {
    /// The server, the cache, the rounds, the examples; a `cache_dir` of `None` caches in
    /// `OUT/.llm-cache`.
    pub config: SynthConfig,
    /// Descriptions synthesized at once (1 to 64).
    pub jobs: usize,
}

/// Synthesis jobs checked: 1 to 64.
pub(crate) fn check_jobs(jobs: usize) -> Result<(), Error> {
    if !(1..=64).contains(&jobs) {
        return Err(
            Error::plain(format!("synthesis jobs: expected 1 to 64, got {jobs}"))
                .of_kind(ErrorKind::Invalid),
        );
    }
    Ok(())
}

/// The settings a configuration is made of (the command's `--rounds`, `--base-url`, …); the
/// server's address, model and key default to the environment ([`ENV_BASE_URL`],
/// [`ENV_MODEL`], [`ENV_API_KEY`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SynthSettings {
    /// Cache completions here (`None`: no cache, unless the caller gives a default).
    pub cache_dir: Option<PathBuf>,
    /// Completions to ask for at most: the first attempt and the repairs.
    pub rounds: usize,
    /// The OpenAI-compatible server's base URL (`None`: the environment's, else llama.cpp's
    /// local server).
    pub base_url: Option<String>,
    /// The model's name (`None`: the environment's, else "default").
    pub model: Option<String>,
    /// The API key, sent as a bearer token (`None`: the environment's).
    pub api_key: Option<String>,
    /// The sampling temperature, 0 to 2 (`None`: send none, for models that accept only their
    /// own).
    pub temperature: Option<f64>,
    /// How long one completion may take before it is retried (at least 1 s).
    pub timeout: Duration,
    /// Retries after a failed attempt (refused connection, timeout, 429, 5xx).
    pub retries: u32,
    /// In-context examples per prompt, the most similar of the library (`None`: every one).
    pub examples: Option<usize>,
    /// Read the example library from this directory (`None`: the one built in).
    pub library: Option<PathBuf>,
    /// Leave out the description's own library program and its near-duplicates.
    pub held_out: bool,
    /// Candidate programs per description (1 to 32; 1: one program, as before searches).
    /// With more, each clean candidate is run on `match_logs` and the one whose matches agree
    /// most with the others' is kept.
    pub candidates: usize,
    /// The logs candidates are run on (none: the bundled sample logs).
    pub match_logs: Vec<PathBuf>,
    /// The limits of one candidate's run on one log.
    pub match_limits: Limits,
    /// Stop asking the server once this many tokens are spent (`None`: no budget).
    pub max_tokens: Option<u64>,
    /// Evidence rounds: the kept program's matches on `match_logs` shown to the model, which
    /// keeps or revises it (0 to 5; `None`: 1 with several candidates, else 0).
    pub evidence_rounds: Option<usize>,
    /// Send the language's grammar in this server's field (`None`: unconstrained answers).
    pub grammar: Option<scenalog_synth::GrammarField>,
}

pub use scenalog_synth::GrammarField;

impl Default for SynthSettings {
    /// `scenalog synth`'s defaults: 3 rounds at temperature 0, 8 examples, one candidate, 300 s
    /// a completion with 4 retries, no cache, no token budget, no grammar; the server from the
    /// environment.
    fn default() -> SynthSettings {
        SynthSettings {
            cache_dir: None,
            rounds: 3,
            base_url: None,
            model: None,
            api_key: None,
            temperature: Some(0.0),
            timeout: Duration::from_secs(300),
            retries: 4,
            examples: Some(8),
            library: None,
            held_out: false,
            candidates: 1,
            match_logs: Vec::new(),
            match_limits: Limits::default(),
            max_tokens: None,
            evidence_rounds: None,
            grammar: None,
        }
    }
}

/// The grammar `--grammar` sends for a program (GBNF; the evidence round's also allows `KEEP`).
pub fn grammar() -> String {
    scenalog_rules::grammar::gbnf(scenalog_rules::grammar::Answer::Program)
}

/// The server a grammar is sent to, by name: `llama-cpp`, `vllm` or `sglang`.
///
/// # Errors
/// Another name: an invalid value naming the choices.
pub fn grammar_field(name: &str) -> Result<GrammarField, Error> {
    match name {
        "llama-cpp" => Ok(GrammarField::LlamaCpp),
        "vllm" => Ok(GrammarField::Vllm),
        "sglang" => Ok(GrammarField::Sglang),
        other => Err(invalid(
            Field::Grammar,
            format!("expected llama-cpp, vllm or sglang, got {other:?}"),
        )),
    }
}

/// The most evidence rounds a synthesis may have.
pub const MAX_EVIDENCE_ROUNDS: usize = 5;

/// A configuration, and the library's examples left out because they do not check clean (for
/// the caller to warn about).
pub struct Configured {
    /// The configuration.
    pub config: SynthConfig,
    /// The examples left out, by name.
    pub left_out: Vec<String>,
}

/// The configuration of `settings`; completions are cached in its `cache_dir`, else in
/// `default_cache` (e.g. `OUT/.llm-cache`), else not at all.
pub fn config(
    settings: &SynthSettings,
    default_cache: Option<PathBuf>,
) -> Result<Configured, Error> {
    if let Some(t) = settings.temperature {
        if !(0.0..=2.0).contains(&t) {
            return Err(Error::plain(format!(
                "temperature: expected a number from 0 to 2, got {t}"
            ))
            .of_kind(ErrorKind::Invalid));
        }
    }
    let mut llm = LlmConfig::from_env();
    llm.temperature = settings.temperature;
    llm.grammar = settings.grammar;
    if let Some(v) = &settings.base_url {
        llm.base_url = v.clone();
    }
    if let Some(v) = &settings.model {
        llm.model = v.clone();
    }
    if let Some(v) = &settings.api_key {
        llm.api_key = Some(v.clone());
    }
    llm.timeout = settings.timeout.max(Duration::from_secs(1));
    llm.max_retries = settings.retries;
    let mut examples = match &settings.library {
        Some(dir) => library::load_dir(dir).map_err(Error::plain)?,
        None => library::embedded(),
    };
    let left_out = library::retain_clean(&mut examples);
    if !(1..=32).contains(&settings.candidates) {
        return Err(invalid(
            Field::Candidates,
            format!("expected 1 to 32, got {}", settings.candidates),
        ));
    }
    let evidence_rounds = settings
        .evidence_rounds
        .unwrap_or(if settings.candidates > 1 { 1 } else { 0 });
    if evidence_rounds > MAX_EVIDENCE_ROUNDS {
        return Err(invalid(
            Field::EvidenceRounds,
            format!("expected 0 to {MAX_EVIDENCE_ROUNDS}, got {evidence_rounds}"),
        ));
    }
    let (matcher, evidence) = if settings.candidates > 1 || evidence_rounds > 0 {
        settings.match_limits.check()?;
        let (m, e) =
            crate::api::synth_search::search_logs(&settings.match_logs, &settings.match_limits)?;
        (Some(m), Some(e))
    } else {
        (None, None)
    };
    Ok(Configured {
        config: SynthConfig {
            llm,
            cache_dir: settings.cache_dir.clone().or(default_cache),
            rounds: settings.rounds,
            library: examples,
            examples: settings.examples,
            held_out: settings.held_out,
            candidates: settings.candidates,
            sample_temperature: scenalog_synth::search::SAMPLE_TEMPERATURE,
            matcher,
            max_tokens: settings.max_tokens,
            evidence_rounds,
            evidence,
        },
        left_out,
    })
}

/// The synthesizer of a configuration (its client, and its cache opened).
pub fn synthesizer(config: SynthConfig) -> Result<Synthesizer, Error> {
    Synthesizer::new(config).map_err(Error::plain)
}

/// The prompt a description would be sent with (`scenalog synth --print-prompt`).
pub fn prompt_text(synth: &Synthesizer, description: &str) -> String {
    prompt::render(&synth.prompt(description))
}

/// One description to synthesize.
pub struct OneRequest {
    /// The description.
    pub description: String,
    /// Write the program here (with its transcript and, when it does not check clean, its
    /// diagnostics beside it) instead of handing it back only.
    pub output: Option<PathBuf>,
    /// Also write the transcript of every round (JSON) here.
    pub transcript: Option<PathBuf>,
}

/// One description synthesized.
pub struct OneOutcome {
    /// Every round, the program and the outcome.
    pub transcript: Transcript,
    /// The transcript file could not be written: why (the program is still good).
    pub transcript_error: Option<String>,
    /// The program's file could not be written: why.
    pub output_error: Option<String>,
    /// Where the last attempt's diagnostics are, when it did not check clean and was written.
    pub diagnostics_file: Option<PathBuf>,
}

impl OneOutcome {
    /// The last attempt's diagnostics for a person (`None` when there is no program), as the
    /// checker renders them (`color` for a terminal).
    pub fn diagnostics_text(&self, color: bool) -> Option<String> {
        let program = self.transcript.program()?;
        let outcome = scenalog_rules::check(
            program,
            &scenalog_rules::CheckOptions {
                require_referred: true,
            },
        );
        Some(scenalog_rules::render_human(
            &outcome.diagnostics,
            program,
            "<synthesized>",
            color,
        ))
    }
}

/// Synthesizes one description, writing its files when asked; an empty description is an
/// error. A server that cannot be reached is the transcript's outcome, not an error.
pub fn synthesize_one(synth: &Synthesizer, request: &OneRequest) -> Result<OneOutcome, Error> {
    if request.description.trim().is_empty() {
        return Err(Error::plain("the description is empty").of_kind(ErrorKind::Invalid));
    }
    let transcript = synth.synthesize(&request.description);
    let transcript_error = request.transcript.as_ref().and_then(|path| {
        scenalog_synth::cache::write_atomic(path, transcript.to_json().as_bytes())
            .err()
            .map(|e| e.to_string())
    });
    let output_error = request.output.as_ref().and_then(|path| {
        write_outputs(path, &transcript)
            .err()
            .map(|e| e.to_string())
    });
    let diagnostics_file = match (&request.output, &transcript.outcome) {
        (
            Some(path),
            Outcome::Failed | Outcome::Unreachable { .. } | Outcome::OverBudget { .. },
        ) => Some(batch::diagnostics_path(path)),
        _ => None,
    };
    Ok(OneOutcome {
        transcript,
        transcript_error,
        output_error,
        diagnostics_file,
    })
}

/// A file of descriptions to synthesize into a directory.
pub struct BatchRequest {
    /// The descriptions, one a line (blank lines and `#` comments skipped).
    pub descriptions: PathBuf,
    /// The directory: one `<slug>.dl` a description, with its transcript.
    pub out: PathBuf,
    /// Descriptions synthesized at once (1 to 64).
    pub jobs: usize,
    /// Draw a progress bar (the command).
    pub progress: bool,
}

/// A batch synthesized: its report, and the output folder still held (one writer a folder)
/// until this is dropped.
pub struct BatchOutcome {
    /// Every description's status and program, and the summary.
    pub report: BatchReport,
    _held: OutputLock,
}

/// Synthesizes every description of the request's file into its directory, holding the folder
/// while it writes (a second batch into it is refused, naming the holder).
pub fn synthesize_batch(
    synth: &Synthesizer,
    request: &BatchRequest,
) -> Result<BatchOutcome, Error> {
    check_jobs(request.jobs)?;
    let descriptions = batch::read_descriptions(&request.descriptions).map_err(Error::plain)?;
    let held = OutputLock::acquire(&request.out).map_err(Error::plain)?;
    let options = BatchOptions {
        out_dir: request.out.clone(),
        jobs: request.jobs,
        progress: request.progress,
    };
    let report = batch::run(synth, &descriptions, &options).map_err(Error::plain)?;
    Ok(BatchOutcome {
        report,
        _held: held,
    })
}

/// The tokens of `u` on one line, with their cost at `price`.
pub fn tokens_line(u: &Usage, price: Option<&Price>) -> String {
    let mut s = format!(
        "tokens: {} uncached input, {} cached input, {} output",
        u.uncached_tokens(),
        u.cached_tokens,
        u.completion_tokens
    );
    if let Some(p) = price {
        s.push_str(&format!(", cost {:.4}", p.cost(u)));
    }
    if u.without_usage > 0 {
        s.push_str(&format!(
            " ({} of {} server answers reported no usage)",
            u.without_usage, u.completions
        ));
    }
    s
}

/// A description set to measure synthesis on (`scenalog synth --eval`).
pub struct EvalRequest {
    /// The descriptions, one a line.
    pub descriptions: PathBuf,
    /// The sample logs each clean program runs on (each subdirectory one AV2 log).
    pub logs: PathBuf,
    /// The ground truth the descriptions that are its prompts are scored against (`None`: the
    /// bundled fixture's, when present).
    pub gt: Option<PathBuf>,
    /// One (log, program) evaluation's limits.
    pub limits: Limits,
    /// Prices per million tokens the report's cost is computed at.
    pub price: Option<Price>,
    /// How the report's per-description errors name the request's fields.
    pub names: Names,
}

/// A description set measured: the report, and why the fixture could not be scored (the rest
/// is reported; the command's exit 1).
pub struct Evaluated {
    /// The report.
    pub report: EvalReport,
    /// The fixture score failed: why.
    pub fixture_error: Option<Message>,
}

/// Synthesizes every description of the request with held-out prompts (`synth`'s
/// configuration should have `held_out` set), runs each clean program on the sample logs, and
/// mines and scores the descriptions that are prompts of the ground truth as `scenalog mine`
/// does. An error means an input is unusable (the command's exit 2).
pub fn evaluate(synth: &Synthesizer, request: &EvalRequest) -> Result<Evaluated, Error> {
    request.limits.check()?;
    let descriptions = batch::read_descriptions(&request.descriptions).map_err(Error::plain)?;
    let gt = request.gt.clone().or_else(|| bundled(SAMPLE_GT));
    if let Some(g) = &gt {
        if !g.is_file() {
            return Err(Error::mentioning(
                "",
                Field::Gt,
                format!(" `{}` is not a file", g.display()),
            ));
        }
    }
    let logs = &request.logs;
    let mut dirs: Vec<PathBuf> = match std::fs::read_dir(logs) {
        Ok(rd) => rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_dir())
            .collect(),
        Err(e) => {
            return Err(Error::mentioning(
                "",
                Field::Logs,
                format!(" `{}`: {e}", logs.display()),
            ))
        }
    };
    dirs.sort();
    let mut scenes = Vec::new();
    for d in &dirs {
        match scenalog_facts::load_scene(d) {
            Ok(s) => scenes.push(s),
            Err(e) => return Err(Error::plain(format!("`{}`: {e}", d.display()))),
        }
    }
    if scenes.is_empty() {
        return Err(Error::mentioning(
            "",
            Field::Logs,
            format!(" `{}` holds no log", logs.display()),
        ));
    }
    let limits = request.limits.for_run(None);
    let extractors: Vec<_> = scenes
        .iter()
        .map(scenalog_extractors::Extractor::new)
        .collect();
    let names = request.names;
    let mut report = scenalog_synth::evaluation::evaluate(synth, &descriptions, |source| {
        let checked = scenalog_rules::check(source, &scenalog_rules::CheckOptions::default())
            .program
            .ok_or("the clean program no longer checks")?;
        let mut n = 0;
        for x in &extractors {
            let ev = crate::pipeline::scenario::evaluate_on(x, &checked, &limits)
                .map_err(|e| e.message("").render(names))?;
            n += ev.size("referred");
        }
        Ok(n)
    });
    report.price = request.price;
    let mut fixture_error = None;
    if let Some(g) = &gt {
        let scratch = std::env::temp_dir();
        match crate::api::synth_fixture::fixture_score(&report, g, logs, &scratch, &limits, names) {
            Ok(f) => report.fixture = f,
            Err(e) => fixture_error = Some(e),
        }
        // With candidates, the score the first candidates would have had, to compare.
        if report.searched() > 0 && fixture_error.is_none() {
            let mut firsts = report.clone();
            for item in firsts.items.iter_mut().filter(|i| i.candidates > 1) {
                item.program = item.first_program.clone();
            }
            match crate::api::synth_fixture::fixture_score(
                &firsts, g, logs, &scratch, &limits, names,
            ) {
                Ok(f) => report.first_fixture = f,
                Err(e) => fixture_error = Some(e),
            }
        }
    }
    Ok(Evaluated {
        report,
        fixture_error,
    })
}

/// Programs synthesized from descriptions.
pub struct Synthesized {
    /// The programs that check clean: their file and text.
    pub programs: Vec<(PathBuf, String)>,
    /// By program file, the clean candidates of the search it was kept from (`--candidates`;
    /// absent for a program from one candidate).
    pub candidates: std::collections::BTreeMap<PathBuf, Vec<String>>,
    /// A message per description that gave none.
    pub problems: Vec<String>,
    /// The batch's one-line summary.
    pub summary: String,
}

/// Synthesizes the descriptions of `file` into OUT/programs (see `scenalog synth
/// --descriptions`), caching completions in `OUT/.llm-cache` unless the configuration names a
/// cache: the programs that check clean, and a failure per description that did not.
pub fn synthesize(
    file: &Path,
    out: &Path,
    synthesis: &Synthesis,
    progress: bool,
) -> Result<Synthesized, Error> {
    let mut config = synthesis.config.clone();
    if config.cache_dir.is_none() {
        config.cache_dir = Some(out.join(".llm-cache"));
    }
    let dir = out.join("programs");
    let report =
        scenalog_synth::programs_for_descriptions(file, &dir, config, synthesis.jobs, progress)
            .map_err(|e| Error::about(Field::Descriptions, e))?;
    let mut programs = Vec::new();
    let mut problems = Vec::new();
    let mut candidates = std::collections::BTreeMap::new();
    for item in report.items {
        match (&item.status, item.program) {
            (ItemStatus::Clean { .. } | ItemStatus::Resumed, Some(p)) => {
                if !item.candidates.is_empty() {
                    candidates.insert(item.path.clone(), item.candidates);
                }
                programs.push((item.path, p))
            }
            (ItemStatus::Failed, _) => problems.push(format!(
                "synthesis of {:?} gave no clean program; the last attempt is in `{}`",
                item.description,
                item.path.display()
            )),
            (ItemStatus::Unreachable { error }, _) => problems.push(format!(
                "synthesis of {:?}: the LLM could not be reached: {error}",
                item.description
            )),
            (ItemStatus::OverBudget { error }, _) => {
                problems.push(format!("synthesis of {:?}: {error}", item.description))
            }
            (ItemStatus::Skipped, _) => problems.push(format!(
                "synthesis of {:?}: not attempted, an earlier description stopped the batch \
                 (the LLM could not be reached, or the token budget was spent)",
                item.description
            )),
            (_, None) => problems.push(format!(
                "synthesis of {:?} gave no program",
                item.description
            )),
        }
    }
    Ok(Synthesized {
        programs,
        candidates,
        problems,
        summary: report.summary.to_string(),
    })
}
