//! Synthesizing Scenalog programs from natural-language descriptions with an LLM.
//!
//! Owns: the prompt (built from the catalog, a summary of the language, the category list and
//! examples chosen from the scenario library), the OpenAI-compatible chat-completions client
//! (timeouts, retries with backoff), extraction of the program from an answer, the repair loop
//! that feeds the checker's diagnostics back to the model (with a transcript of every round), the
//! on-disk completion cache, and batch synthesis of many descriptions into a directory of `.dl`
//! files.
//!
//! Does not own: the rule language or its checker (the `rules` crate, which this calls through
//! [`scenalog_rules::check()`]), the catalog (the `facts` crate), or mining with the programs (the
//! root package's pipeline, which calls [`batch::run`]).
//!
//! The entry point is [`Synthesizer`]: made from a [`SynthConfig`], it turns one description into a
//! [`repair::Transcript`] ([`Synthesizer::synthesize`]); [`batch::run`] does many at once.

#![warn(missing_docs)]

pub mod batch;
pub mod cache;
pub mod client;
pub mod diagnostics;
pub mod evaluation;
pub mod evidence;
pub mod extract;
pub mod library;
pub mod prompt;
pub mod repair;
pub mod search;
pub mod slug;
pub mod transcript;
pub mod usage;

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

pub use batch::{BatchItem, BatchOptions, BatchReport, ItemStatus};
pub use cache::Cache;
pub use client::{Client, ClientError, GrammarField, LlmConfig, Message};
pub use evidence::{Evidence, EvidenceRound, Verdict};
pub use library::Example;
pub use repair::{Outcome, Round, Transcript};
pub use scenalog_rules::grammar::Answer;
pub use search::{MatchKey, Matcher, Search};
pub use usage::{Price, Usage};

/// Errors of synthesis that are not the model's or the server's fault: files and directories.
#[derive(Debug, thiserror::Error)]
pub enum SynthError {
    /// A file or directory could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What went wrong.
        source: std::io::Error,
    },
    /// An input file is not a readable regular file (missing, a FIFO, a device, a directory, a
    /// symlink loop, too large, not UTF-8).
    #[error("{path}: {problem}")]
    File {
        /// The file.
        path: PathBuf,
        /// What it is or why it cannot be read.
        problem: scenalog_input::FileProblem,
    },
    /// A file's content is not what was expected.
    #[error("{path}: {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the line when there is one.
        message: String,
    },
}

impl SynthError {
    /// Reads a text input file through `scenalog-input` (never blocking on a FIFO, never past
    /// [`scenalog_input::TEXT_LIMIT`]).
    pub(crate) fn read_text(path: &std::path::Path) -> Result<String, SynthError> {
        scenalog_input::read_text_file(path, scenalog_input::TEXT_LIMIT).map_err(|problem| {
            SynthError::File {
                path: path.to_path_buf(),
                problem,
            }
        })
    }

    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> SynthError {
        SynthError::Io {
            path: path.into(),
            source,
        }
    }
}

/// Everything a [`Synthesizer`] needs.
#[derive(Debug, Clone)]
pub struct SynthConfig {
    /// The LLM server and model.
    pub llm: LlmConfig,
    /// Where completions are cached (`None`: no cache).
    pub cache_dir: Option<PathBuf>,
    /// How many completions to ask for at most (the first attempt and the repairs), at least 1.
    pub rounds: usize,
    /// The in-context examples to choose from.
    pub library: Vec<Example>,
    /// How many examples go into a prompt: the most similar to the description (`None`: all).
    pub examples: Option<usize>,
    /// Held-out prompts: leave out the description's own library program and its
    /// near-duplicates ([`prompt::held_out`]), to measure synthesis without showing the answer.
    pub held_out: bool,
    /// Candidate programs per description (at least 1): the first asked as today, the others
    /// sampled at [`SynthConfig::sample_temperature`]; with more than one, the program kept is
    /// the one whose matches agree most with the others' ([`search`]).
    pub candidates: usize,
    /// The temperature the candidates after the first are sampled at.
    pub sample_temperature: f64,
    /// What a candidate program matches on the logs (`None`: candidates are not run, and the
    /// first clean one is kept).
    pub matcher: Option<Matcher>,
    /// Stop asking the server once this many tokens (prompt and completion, as it reports
    /// them) are spent by this synthesizer (`None`: no budget). Cached answers cost nothing.
    pub max_tokens: Option<u64>,
    /// Evidence rounds after the search: the kept program's matches shown to the model, which
    /// keeps it or revises it ([`evidence`]); 0: none. Needs [`SynthConfig::evidence`].
    pub evidence_rounds: usize,
    /// What a program matches on the logs, in words (`None`: no evidence rounds).
    pub evidence: Option<Evidence>,
}

impl SynthConfig {
    /// A configuration with the server from `llm`, no cache, 3 rounds, the embedded library
    /// (the programs that check clean) and at most [`prompt::DEFAULT_EXAMPLES`] examples.
    pub fn new(llm: LlmConfig) -> SynthConfig {
        let mut examples = library::embedded();
        library::retain_clean(&mut examples);
        SynthConfig {
            llm,
            cache_dir: None,
            rounds: 3,
            library: examples,
            examples: Some(prompt::DEFAULT_EXAMPLES),
            held_out: false,
            candidates: 1,
            sample_temperature: search::SAMPLE_TEMPERATURE,
            matcher: None,
            max_tokens: None,
            evidence_rounds: 0,
            evidence: None,
        }
    }
}

/// How many completions a [`Synthesizer`] got from the server and from the cache.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Stats {
    /// Completions answered by the server (each may have taken several HTTP attempts).
    pub requests: usize,
    /// Completions answered by the cache.
    pub cache_hits: usize,
    /// Tokens the server reported for its completions.
    pub usage: Usage,
}

/// Turns descriptions into checked programs: the client, the cache and the prompt's examples.
/// Shareable across threads.
#[derive(Debug)]
pub struct Synthesizer {
    config: SynthConfig,
    client: Client,
    cache: Option<Cache>,
    requests: AtomicUsize,
    cache_hits: AtomicUsize,
    usage: Mutex<Usage>,
}

impl Synthesizer {
    /// Makes the client and opens (creating it if needed) the cache directory.
    pub fn new(config: SynthConfig) -> Result<Synthesizer, SynthError> {
        let cache = match &config.cache_dir {
            Some(dir) => Some(Cache::open(dir)?),
            None => None,
        };
        Ok(Synthesizer {
            client: Client::new(config.llm.clone()),
            config,
            cache,
            requests: AtomicUsize::new(0),
            cache_hits: AtomicUsize::new(0),
            usage: Mutex::new(Usage::default()),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &SynthConfig {
        &self.config
    }

    /// The first request's messages for a description (what `--print-prompt` shows).
    pub fn prompt(&self, description: &str) -> Vec<Message> {
        if self.config.held_out {
            let library = prompt::held_out(description, &self.config.library);
            prompt::messages(description, &library, self.config.examples)
        } else {
            prompt::messages(description, &self.config.library, self.config.examples)
        }
    }

    /// Synthesizes one description: prompt, then up to `rounds` completions, each checked and
    /// repaired on diagnostics; with several [`SynthConfig::candidates`], that for each
    /// candidate and the one kept chosen by what they match ([`search::run`]), then shown its
    /// matches in [`SynthConfig::evidence_rounds`] ([`evidence`]). Never fails: an unreachable
    /// server is the transcript's outcome.
    pub fn synthesize(&self, description: &str) -> Transcript {
        if self.config.candidates > 1 || self.evidence_rounds() > 0 {
            search::run(self, description)
        } else {
            repair::run(self, description)
        }
    }

    /// The evidence rounds a synthesis has: the configured number when there is evidence to
    /// show, else none.
    pub fn evidence_rounds(&self) -> usize {
        match self.config.evidence {
            Some(_) => self.config.evidence_rounds,
            None => 0,
        }
    }

    /// Completions so far, from the server and from the cache.
    pub fn stats(&self) -> Stats {
        Stats {
            requests: self.requests.load(Ordering::Relaxed),
            cache_hits: self.cache_hits.load(Ordering::Relaxed),
            usage: *self.usage.lock().unwrap_or_else(|e| e.into_inner()),
        }
    }

    /// One completion: from the cache when it has one, else from the server, stored in the cache
    /// before it is returned. Also returned: whether it came from the cache, and the tokens the
    /// server reported (zero from the cache; [`Usage::missing`] when the server reported none).
    pub fn complete(&self, messages: &[Message]) -> Result<(String, bool, Usage), ClientError> {
        self.complete_sample(messages, 0)
    }

    /// [`Synthesizer::complete`] for candidate `sample` of a search: sample 0 is the same
    /// completion; the others are sampled at [`SynthConfig::sample_temperature`] and cached
    /// under their own keys ([`Cache::sample_key`]).
    pub fn complete_sample(
        &self,
        messages: &[Message],
        sample: usize,
    ) -> Result<(String, bool, Usage), ClientError> {
        self.complete_answer(messages, sample, Answer::Program)
    }

    /// [`Synthesizer::complete_sample`] for an answer of this kind (a program, or a program or
    /// `KEEP`): what grammar is sent when [`LlmConfig::grammar`] is set. A constrained answer is
    /// cached apart from an unconstrained one.
    pub fn complete_answer(
        &self,
        messages: &[Message],
        sample: usize,
        answer: Answer,
    ) -> Result<(String, bool, Usage), ClientError> {
        let model = match self.config.llm.grammar {
            Some(_) => format!("{} (grammar {answer:?})", self.config.llm.model),
            None => self.config.llm.model.clone(),
        };
        let key = Cache::sample_key(&model, messages, sample);
        if let Some(cache) = &self.cache {
            if let Some(text) = cache.get(&key) {
                self.cache_hits.fetch_add(1, Ordering::Relaxed);
                return Ok((text, true, Usage::default()));
            }
        }
        if let Some(limit) = self.config.max_tokens {
            let used = *self.usage.lock().unwrap_or_else(|e| e.into_inner());
            let spent = used.prompt_tokens + used.completion_tokens;
            if spent >= limit {
                return Err(ClientError::Budget { limit, spent });
            }
        }
        let temperature = if sample == 0 {
            self.config.llm.temperature
        } else {
            Some(self.config.sample_temperature)
        };
        let answer = self.client.complete_as(messages, temperature, answer)?;
        let usage = answer.usage.unwrap_or_else(Usage::missing);
        self.requests.fetch_add(1, Ordering::Relaxed);
        {
            let mut total = self.usage.lock().unwrap_or_else(|e| e.into_inner());
            *total = total.add(&usage);
        }
        let text = answer.text;
        if let Some(cache) = &self.cache {
            if let Err(e) = cache.put(&key, &self.config.llm.model, messages, &text) {
                // The completion is still good; say the cache could not keep it.
                eprintln!("warning: could not cache a completion: {e}");
            }
        }
        Ok((text, false, usage))
    }
}

/// For `scenalog mine --descriptions FILE`: synthesizes (or takes from `out_dir` and the cache)
/// a program for every description of `descriptions_file` (one a line), writing them to
/// `out_dir` as [`batch::run`] does. The report's items hold the programs in file order; mine
/// those whose status is [`ItemStatus::Clean`] or [`ItemStatus::Resumed`].
pub fn programs_for_descriptions(
    descriptions_file: &std::path::Path,
    out_dir: &std::path::Path,
    config: SynthConfig,
    jobs: usize,
    progress: bool,
) -> Result<BatchReport, SynthError> {
    let descriptions = batch::read_descriptions(descriptions_file)?;
    let synth = Synthesizer::new(config)?;
    batch::run(
        &synth,
        &descriptions,
        &BatchOptions {
            out_dir: out_dir.to_path_buf(),
            jobs,
            progress,
        },
    )
}
