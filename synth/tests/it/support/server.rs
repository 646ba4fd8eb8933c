//! A scripted OpenAI-compatible chat-completions server on 127.0.0.1 for tests: it records every
//! request and answers each from a handler (or a fixed script), one thread per connection,
//! bounded in time (it stops accepting after a minute or when dropped).

#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// What the server sends back for one request.
#[derive(Debug, Clone)]
pub enum Reply {
    /// 200 with a chat completion whose content is this text.
    Completion(String),
    /// 200 with a chat completion of this text carrying this `usage` object.
    WithUsage(String, serde_json::Value),
    /// This status with a JSON error body `{"error": {"message": …}}` and maybe `Retry-After`.
    Error {
        status: u16,
        message: String,
        retry_after: Option<String>,
    },
    /// This status and this body, as is.
    Raw { status: u16, body: String },
    /// Wait this long, then close the connection without answering.
    Hang(Duration),
}

/// The answer to a program request: a completion holding the program in a code block.
pub fn program(code: &str) -> Reply {
    Reply::Completion(format!(
        "Here is the program:\n\n```scenalog\n{code}\n```\n"
    ))
}

/// `reply` (a [`Reply::Completion`]) with a `usage` of `prompt` and `completion` tokens, and
/// `prompt_tokens_details.cached_tokens` when `cached` is given.
pub fn with_usage(reply: Reply, prompt: u64, cached: Option<u64>, completion: u64) -> Reply {
    let Reply::Completion(text) = reply else {
        panic!("with_usage takes a completion");
    };
    let mut usage = serde_json::json!({
        "prompt_tokens": prompt,
        "completion_tokens": completion,
        "total_tokens": prompt + completion,
    });
    if let Some(c) = cached {
        usage["prompt_tokens_details"] = serde_json::json!({ "cached_tokens": c });
    }
    Reply::WithUsage(text, usage)
}

/// One request as received.
#[derive(Debug, Clone)]
pub struct Request {
    /// The request line, e.g. `POST /v1/chat/completions HTTP/1.1`.
    pub line: String,
    /// Headers, names lower-cased.
    pub headers: Vec<(String, String)>,
    /// The body parsed as JSON (`Null` when it is not JSON).
    pub json: serde_json::Value,
}

impl Request {
    /// A header's value.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// The content of the last message.
    pub fn last_message(&self) -> String {
        self.messages().last().cloned().unwrap_or_default()
    }

    /// The contents of the messages.
    pub fn messages(&self) -> Vec<String> {
        self.json["messages"]
            .as_array()
            .map(|a| {
                a.iter()
                    .map(|m| m["content"].as_str().unwrap_or_default().to_string())
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The description the first user message asks for (its last line).
    pub fn description(&self) -> String {
        self.messages()
            .get(1)
            .and_then(|m| m.trim_end().lines().last().map(str::to_string))
            .unwrap_or_default()
    }
}

type Handler = dyn Fn(usize, &Request) -> Reply + Send + Sync;

/// The running server.
pub struct Server {
    port: u16,
    requests: Arc<Mutex<Vec<Request>>>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Server {
    /// A server answering request `i` (0-based, in arrival order) with `handler(i, request)`.
    pub fn start(handler: impl Fn(usize, &Request) -> Reply + Send + Sync + 'static) -> Server {
        let listener = TcpListener::bind("127.0.0.1:0").expect("bind 127.0.0.1:0");
        listener.set_nonblocking(true).expect("nonblocking");
        let port = listener.local_addr().expect("local addr").port();
        let requests = Arc::new(Mutex::new(Vec::new()));
        let stop = Arc::new(AtomicBool::new(false));
        let handler: Arc<Handler> = Arc::new(handler);
        let thread = {
            let requests = Arc::clone(&requests);
            let stop = Arc::clone(&stop);
            std::thread::spawn(move || {
                let deadline = Instant::now() + Duration::from_secs(60);
                let mut workers = Vec::new();
                while !stop.load(Ordering::Relaxed) && Instant::now() < deadline {
                    match listener.accept() {
                        Ok((stream, _)) => {
                            let requests = Arc::clone(&requests);
                            let handler = Arc::clone(&handler);
                            workers.push(std::thread::spawn(move || {
                                serve(stream, &requests, &*handler)
                            }));
                        }
                        Err(_) => std::thread::sleep(Duration::from_millis(2)),
                    }
                }
                for w in workers {
                    let _ = w.join();
                }
            })
        };
        Server {
            port,
            requests,
            stop,
            thread: Some(thread),
        }
    }

    /// A server answering the `i`-th request with `script[i]` (and HTTP 418 past its end).
    pub fn scripted(script: Vec<Reply>) -> Server {
        Server::start(move |i, _| {
            script.get(i).cloned().unwrap_or(Reply::Error {
                status: 418,
                message: "the test script has no more answers".into(),
                retry_after: None,
            })
        })
    }

    /// The base URL to give the client.
    pub fn base_url(&self) -> String {
        format!("http://127.0.0.1:{}/v1", self.port)
    }

    /// Every request so far.
    pub fn requests(&self) -> Vec<Request> {
        self.requests.lock().expect("requests lock").clone()
    }

    /// How many requests so far.
    pub fn count(&self) -> usize {
        self.requests.lock().expect("requests lock").len()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn serve(stream: TcpStream, requests: &Mutex<Vec<Request>>, handler: &Handler) {
    let _ = stream.set_nonblocking(false);
    let _ = stream.set_read_timeout(Some(Duration::from_secs(10)));
    let mut reader = BufReader::new(match stream.try_clone() {
        Ok(s) => s,
        Err(_) => return,
    });
    let mut line = String::new();
    if reader.read_line(&mut line).is_err() || line.is_empty() {
        return;
    }
    let mut headers = Vec::new();
    loop {
        let mut h = String::new();
        if reader.read_line(&mut h).is_err() {
            return;
        }
        let h = h.trim_end();
        if h.is_empty() {
            break;
        }
        if let Some((n, v)) = h.split_once(':') {
            headers.push((n.trim().to_ascii_lowercase(), v.trim().to_string()));
        }
    }
    let len: usize = headers
        .iter()
        .find(|(n, _)| n == "content-length")
        .and_then(|(_, v)| v.parse().ok())
        .unwrap_or(0);
    let mut body = vec![0u8; len];
    if reader.read_exact(&mut body).is_err() {
        return;
    }
    let request = Request {
        line: line.trim_end().to_string(),
        headers,
        json: serde_json::from_slice(&body).unwrap_or(serde_json::Value::Null),
    };
    let index = {
        let mut r = requests.lock().expect("requests lock");
        r.push(request.clone());
        r.len() - 1
    };
    let completion = |text: String| {
        serde_json::json!({
            "id": format!("cmpl-{index}"),
            "object": "chat.completion",
            "model": request.json["model"],
            "choices": [{"index": 0, "message": {"role": "assistant", "content": text}, "finish_reason": "stop"}],
        })
    };
    let (status, extra, body) = match handler(index, &request) {
        Reply::Completion(text) => (200, String::new(), completion(text).to_string()),
        Reply::WithUsage(text, usage) => {
            let mut body = completion(text);
            body["usage"] = usage;
            (200, String::new(), body.to_string())
        }
        Reply::Error {
            status,
            message,
            retry_after,
        } => (
            status,
            retry_after
                .map(|r| format!("Retry-After: {r}\r\n"))
                .unwrap_or_default(),
            serde_json::json!({"error": {"message": message, "type": "test"}}).to_string(),
        ),
        Reply::Raw { status, body } => (status, String::new(), body),
        Reply::Hang(d) => {
            std::thread::sleep(d);
            return;
        }
    };
    let mut stream = stream;
    let _ = write!(
        stream,
        "HTTP/1.1 {status} X\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n{extra}\r\n{body}",
        body.len()
    );
    let _ = stream.flush();
}
