//! The OpenAI-compatible chat-completions client: `POST {base}/chat/completions` with the model,
//! the messages and temperature 0, as served by OpenAI, vLLM, llama.cpp's server, Ollama and most
//! hosted models.
//!
//! Transport errors (refused connections, timeouts), 429 and 5xx answers are retried with
//! exponential backoff (honouring `Retry-After`); any other 4xx is reported at once with the
//! server's own message. An answer that is not the protocol's JSON is reported, not retried.

use std::time::Duration;

use scenalog_rules::grammar::Answer;

use serde::{Deserialize, Serialize};

use crate::usage::Usage;

/// One chat message.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Message {
    /// "system", "user" or "assistant".
    pub role: String,
    /// The text.
    pub content: String,
}

impl Message {
    /// A system message.
    pub fn system(content: impl Into<String>) -> Message {
        Message {
            role: "system".into(),
            content: content.into(),
        }
    }

    /// A user message.
    pub fn user(content: impl Into<String>) -> Message {
        Message {
            role: "user".into(),
            content: content.into(),
        }
    }

    /// An assistant message.
    pub fn assistant(content: impl Into<String>) -> Message {
        Message {
            role: "assistant".into(),
            content: content.into(),
        }
    }
}

/// Environment variable holding the server's base URL.
pub const ENV_BASE_URL: &str = "SCENALOG_LLM_BASE_URL";
/// Environment variable holding the model name.
pub const ENV_MODEL: &str = "SCENALOG_LLM_MODEL";
/// Environment variable holding the API key.
pub const ENV_API_KEY: &str = "SCENALOG_LLM_API_KEY";
/// Base URL when neither a flag nor the environment gives one: llama.cpp's server on its default port.
pub const DEFAULT_BASE_URL: &str = "http://127.0.0.1:8080/v1";
/// Model name when neither a flag nor the environment gives one (llama.cpp's server ignores it).
pub const DEFAULT_MODEL: &str = "default";

/// Where the server is and how patiently to talk to it.
#[derive(Debug, Clone, PartialEq)]
pub struct LlmConfig {
    /// Base URL, e.g. `http://127.0.0.1:8080/v1` (`/chat/completions` is appended unless the URL
    /// already ends with it).
    pub base_url: String,
    /// Model name sent with each request.
    pub model: String,
    /// Bearer token, if the server wants one.
    pub api_key: Option<String>,
    /// Limit on one whole HTTP exchange (a completion of a slow local model takes a while).
    pub timeout: Duration,
    /// Limit on opening the connection.
    pub connect_timeout: Duration,
    /// Retries after the first attempt for transport errors, 429 and 5xx.
    pub max_retries: u32,
    /// Wait before the first retry; doubled for each further one.
    pub backoff: Duration,
    /// Longest wait between attempts (also caps `Retry-After`).
    pub max_backoff: Duration,
    /// Sampling temperature (0: as deterministic as the server allows; `None`: not sent, for
    /// models that accept only their default, such as OpenAI's reasoning models).
    pub temperature: Option<f64>,
    /// Send the language's grammar in this server's field, so an answer cannot fail to parse
    /// (`None`: unconstrained).
    pub grammar: Option<GrammarField>,
}

/// Where a server takes a grammar to constrain decoding to (GBNF in each case).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GrammarField {
    /// llama.cpp's server: `grammar`.
    LlamaCpp,
    /// vLLM: `structured_outputs: {"grammar": …}`.
    Vllm,
    /// SGLang: `ebnf`.
    Sglang,
}

impl GrammarField {
    /// Puts `grammar` into a request body.
    pub fn put(self, body: &mut serde_json::Value, grammar: String) {
        match self {
            GrammarField::LlamaCpp => body["grammar"] = serde_json::json!(grammar),
            GrammarField::Vllm => {
                body["structured_outputs"] = serde_json::json!({ "grammar": grammar })
            }
            GrammarField::Sglang => body["ebnf"] = serde_json::json!(grammar),
        }
    }
}

impl Default for LlmConfig {
    fn default() -> Self {
        LlmConfig {
            base_url: DEFAULT_BASE_URL.into(),
            model: DEFAULT_MODEL.into(),
            api_key: None,
            timeout: Duration::from_secs(300),
            connect_timeout: Duration::from_secs(10),
            max_retries: 4,
            backoff: Duration::from_secs(1),
            max_backoff: Duration::from_secs(60),
            temperature: Some(0.0),
            grammar: None,
        }
    }
}

impl LlmConfig {
    /// The defaults, with base URL, model and key taken from `SCENALOG_LLM_BASE_URL`,
    /// `SCENALOG_LLM_MODEL` and `SCENALOG_LLM_API_KEY` when set and not empty.
    pub fn from_env() -> LlmConfig {
        let var = |name: &str| std::env::var(name).ok().filter(|v| !v.trim().is_empty());
        let mut c = LlmConfig::default();
        if let Some(v) = var(ENV_BASE_URL) {
            c.base_url = v;
        }
        if let Some(v) = var(ENV_MODEL) {
            c.model = v;
        }
        c.api_key = var(ENV_API_KEY);
        c
    }

    /// The chat-completions endpoint.
    pub fn endpoint(&self) -> String {
        let base = self.base_url.trim().trim_end_matches('/');
        if base.ends_with("/chat/completions") {
            base.to_string()
        } else {
            format!("{base}/chat/completions")
        }
    }
}

/// Why no completion came back.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClientError {
    /// The server could not be reached or did not answer in time, after every retry.
    #[error("could not reach the LLM server at {url} ({attempts} attempts): {message}")]
    Unreachable {
        /// The endpoint.
        url: String,
        /// How many attempts were made.
        attempts: u32,
        /// The last transport error.
        message: String,
    },
    /// The server answered with an HTTP error that retrying does not fix (a 4xx other than
    /// 429), or with 429/5xx on every attempt.
    #[error("the LLM server at {url} answered HTTP {status} ({attempts} attempts): {message}")]
    Status {
        /// The endpoint.
        url: String,
        /// The HTTP status.
        status: u16,
        /// How many attempts were made.
        attempts: u32,
        /// The server's own error message (or the start of its body).
        message: String,
    },
    /// The server answered 2xx with something that is not a chat completion.
    #[error("the LLM server at {url} sent an answer that is not a chat completion: {message}")]
    Malformed {
        /// The endpoint.
        url: String,
        /// What is wrong with it.
        message: String,
    },
    /// The token budget (`--max-tokens`) was spent before this completion was asked for.
    #[error(
        "the token budget of {limit} is spent ({spent} tokens used so far); nothing more is asked \
         (raise --max-tokens; completions already answered are in the cache)"
    )]
    Budget {
        /// The budget, in prompt and completion tokens.
        limit: u64,
        /// The tokens the server reported so far.
        spent: u64,
    },
}

/// One answer: the assistant's text and the tokens the server says it used.
#[derive(Debug, Clone, PartialEq)]
pub struct Completion {
    /// `choices[0].message.content`.
    pub text: String,
    /// The answer's `usage` (`None`: it had none, or an unusable one).
    pub usage: Option<Usage>,
}

/// A chat-completions client. Cheap to share between threads.
#[derive(Debug)]
pub struct Client {
    config: LlmConfig,
    agent: ureq::Agent,
}

/// One attempt's result, deciding whether to retry.
enum Attempt {
    Done(Completion),
    Retry {
        message: String,
        status: Option<u16>,
        wait: Option<Duration>,
    },
    Fail(ClientError),
}

impl Client {
    /// A client for `config`'s server.
    pub fn new(config: LlmConfig) -> Client {
        let agent: ureq::Agent = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .timeout_global(Some(config.timeout))
            .timeout_connect(Some(config.connect_timeout))
            .user_agent(concat!("scenalog/", env!("CARGO_PKG_VERSION")))
            .build()
            .into();
        Client { config, agent }
    }

    /// The configuration.
    pub fn config(&self) -> &LlmConfig {
        &self.config
    }

    /// Asks for one completion of `messages` and returns the assistant's text.
    pub fn complete(&self, messages: &[Message]) -> Result<String, ClientError> {
        self.complete_with_usage(messages).map(|c| c.text)
    }

    /// Asks for one completion of `messages`: the assistant's text and the server's `usage`.
    pub fn complete_with_usage(&self, messages: &[Message]) -> Result<Completion, ClientError> {
        self.complete_at(messages, self.config.temperature)
    }

    /// [`Client::complete_with_usage`] at this sampling temperature (`None`: none sent) instead
    /// of the configuration's: a candidate sampled for a search.
    pub fn complete_at(
        &self,
        messages: &[Message],
        temperature: Option<f64>,
    ) -> Result<Completion, ClientError> {
        self.complete_as(messages, temperature, Answer::Program)
    }

    /// [`Client::complete_at`] for an answer of this kind: with a configured
    /// [`LlmConfig::grammar`], the grammar of `answer` is sent with the request.
    pub fn complete_as(
        &self,
        messages: &[Message],
        temperature: Option<f64>,
        answer: Answer,
    ) -> Result<Completion, ClientError> {
        let url = self.config.endpoint();
        let mut body = serde_json::json!({
            "model": self.config.model,
            "messages": messages,
            "stream": false,
        });
        if let Some(t) = temperature {
            body["temperature"] = serde_json::json!(t);
        }
        if let Some(field) = self.config.grammar {
            field.put(&mut body, scenalog_rules::grammar::gbnf(answer));
        }
        let body = body.to_string();
        let mut attempts = 0u32;
        loop {
            attempts += 1;
            let (message, status, wait) = match self.attempt(&url, &body) {
                Attempt::Done(text) => return Ok(text),
                Attempt::Fail(e) => return Err(with_attempts(e, attempts)),
                Attempt::Retry {
                    message,
                    status,
                    wait,
                } => (message, status, wait),
            };
            if attempts > self.config.max_retries {
                return Err(match status {
                    Some(status) => ClientError::Status {
                        url,
                        status,
                        attempts,
                        message,
                    },
                    None => ClientError::Unreachable {
                        url,
                        attempts,
                        message,
                    },
                });
            }
            let backoff = self
                .config
                .backoff
                .saturating_mul(1u32 << (attempts - 1).min(16));
            let wait = wait.unwrap_or(backoff).min(self.config.max_backoff);
            std::thread::sleep(wait);
        }
    }

    fn attempt(&self, url: &str, body: &str) -> Attempt {
        let mut request = self
            .agent
            .post(url)
            .header("Content-Type", "application/json");
        if let Some(key) = &self.config.api_key {
            request = request.header("Authorization", &format!("Bearer {key}"));
        }
        let mut response = match request.send(body) {
            Ok(r) => r,
            Err(e) => {
                return Attempt::Retry {
                    message: e.to_string(),
                    status: None,
                    wait: None,
                }
            }
        };
        let status = response.status().as_u16();
        let retry_after = response
            .headers()
            .get("retry-after")
            .and_then(|v| v.to_str().ok())
            .and_then(parse_retry_after);
        let text = match response
            .body_mut()
            .with_config()
            .limit(64 * 1024 * 1024)
            .read_to_string()
        {
            Ok(t) => t,
            Err(e) => {
                // The body broke off (a timeout or a dropped connection): a transport error.
                return Attempt::Retry {
                    message: format!("reading the answer: {e}"),
                    status: None,
                    wait: None,
                };
            }
        };
        if status == 429 || (500..600).contains(&status) {
            return Attempt::Retry {
                message: error_message(&text),
                status: Some(status),
                wait: retry_after,
            };
        }
        if !(200..300).contains(&status) {
            return Attempt::Fail(ClientError::Status {
                url: url.to_string(),
                status,
                attempts: 0,
                message: error_message(&text),
            });
        }
        match parse_completion(&text) {
            Ok(t) => Attempt::Done(t),
            Err(message) => Attempt::Fail(ClientError::Malformed {
                url: url.to_string(),
                message,
            }),
        }
    }
}

fn with_attempts(e: ClientError, n: u32) -> ClientError {
    match e {
        ClientError::Status {
            url,
            status,
            message,
            ..
        } => ClientError::Status {
            url,
            status,
            attempts: n,
            message,
        },
        other => other,
    }
}

/// `Retry-After` in seconds (integer or decimal); an HTTP date is not honoured (backoff is used).
fn parse_retry_after(v: &str) -> Option<Duration> {
    let secs: f64 = v.trim().parse().ok()?;
    (secs.is_finite() && secs >= 0.0).then(|| Duration::from_secs_f64(secs.min(3600.0)))
}

/// The server's error message: OpenAI's `{"error": {"message": …}}`, Ollama's `{"error": "…"}`,
/// `{"message": …}`, or the start of the body.
fn error_message(body: &str) -> String {
    if let Ok(v) = serde_json::from_str::<serde_json::Value>(body) {
        let found = v
            .pointer("/error/message")
            .or_else(|| v.get("error"))
            .or_else(|| v.get("message"))
            .or_else(|| v.get("detail"));
        if let Some(found) = found {
            return match found.as_str() {
                Some(s) => s.to_string(),
                None => found.to_string(),
            };
        }
    }
    let body = body.trim();
    if body.is_empty() {
        return "(empty body)".into();
    }
    let mut cut: String = body.chars().take(500).collect();
    if cut.len() < body.len() {
        cut.push('…');
    }
    cut
}

/// The assistant's text from a chat-completions answer, `choices[0].message.content`, and its
/// `usage`.
fn parse_completion(body: &str) -> Result<Completion, String> {
    let v: serde_json::Value = serde_json::from_str(body).map_err(|e| {
        let start: String = body.chars().take(200).collect();
        format!("invalid JSON ({e}); the answer began {start:?}")
    })?;
    let choice = v
        .get("choices")
        .and_then(|c| c.get(0))
        .ok_or_else(|| "no `choices[0]` in the answer".to_string())?;
    let usage = Usage::from_answer(&v);
    let text = match choice.pointer("/message/content") {
        Some(serde_json::Value::String(s)) => s.clone(),
        // A reasoning model that spent every token thinking: an empty answer, which the repair
        // loop reports back as an answer with no program.
        Some(serde_json::Value::Null) => String::new(),
        Some(other) => {
            return Err(format!(
                "`choices[0].message.content` is {other}, not a string"
            ))
        }
        None => return Err("no `choices[0].message.content` in the answer".into()),
    };
    Ok(Completion { text, usage })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoint_appends_the_path_once() {
        let mut c = LlmConfig {
            base_url: "http://h:1/v1/".into(),
            ..LlmConfig::default()
        };
        assert_eq!(c.endpoint(), "http://h:1/v1/chat/completions");
        c.base_url = "http://h:1/v1/chat/completions".into();
        assert_eq!(c.endpoint(), "http://h:1/v1/chat/completions");
    }

    #[test]
    fn error_messages_of_common_servers() {
        assert_eq!(
            error_message(r#"{"error":{"message":"bad key","type":"auth"}}"#),
            "bad key"
        );
        assert_eq!(
            error_message(r#"{"error":"model not found"}"#),
            "model not found"
        );
        assert_eq!(error_message("  "), "(empty body)");
        assert_eq!(error_message("Bad Gateway"), "Bad Gateway");
    }

    #[test]
    fn completions_parse_or_say_why_not() {
        let ok = r#"{"choices":[{"message":{"role":"assistant","content":"hi"}}]}"#;
        assert_eq!(parse_completion(ok).map(|c| c.text), Ok("hi".into()));
        let null = r#"{"choices":[{"message":{"role":"assistant","content":null}}]}"#;
        assert_eq!(parse_completion(null).map(|c| c.text), Ok(String::new()));
        assert!(parse_completion("{not json")
            .unwrap_err()
            .contains("invalid JSON"));
        assert!(parse_completion(r#"{"choices":[]}"#)
            .unwrap_err()
            .contains("choices[0]"));
        assert!(
            parse_completion(r#"{"choices":[{"message":{"content":3}}]}"#)
                .unwrap_err()
                .contains("not a string")
        );
    }

    #[test]
    fn retry_after_seconds() {
        assert_eq!(parse_retry_after("2"), Some(Duration::from_secs(2)));
        assert_eq!(parse_retry_after(" 0.5 "), Some(Duration::from_millis(500)));
        assert_eq!(parse_retry_after("Wed, 21 Oct 2015 07:28:00 GMT"), None);
        assert_eq!(parse_retry_after("-1"), None);
    }
}
