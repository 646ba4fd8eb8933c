//! `scenalog studio`: a local web app to write a rule and watch its matches. The page (the files
//! of `studio/`, compiled into the binary: nothing is fetched from a network) edits a program,
//! shows the checker's diagnostics as it is typed, re-mines the open logs on every clean edit,
//! draws a log from above with a time scrubber, and explains a clicked track at the frame shown;
//! with an LLM server configured, it also writes a rule from a description.
//! Every answer comes from [`crate::api::studio`]; this module maps HTTP (axum) to it.
//!
//! It listens on 127.0.0.1 unless `--address` names another address and
//! `--expose-logs-to-network` says the logs may be read from there. Requests must name the
//! studio's own host (a page of another site rebinding its name to this machine is refused) and
//! may not come from another origin; bodies are capped. Ctrl-C (or SIGTERM) stops it cleanly.

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::{DefaultBodyLimit, Query, Request, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use serde::Deserialize;
use serde_json::{json, Value as Json};

use crate::api::studio::{self, Studio, StudioRequest, DEFAULT_PORT, MAX_PROGRAM_BYTES};
use crate::api::synth::{SynthSettings, ENV_BASE_URL};
use crate::api::{Limits, Names};

/// The page and its script and style, served as they are in the repository.
const INDEX_HTML: &str = include_str!("../../studio/index.html");
const STUDIO_JS: &str = include_str!("../../studio/studio.js");
const STUDIO_CSS: &str = include_str!("../../studio/studio.css");

/// Arguments of `scenalog studio`.
#[derive(clap::Args)]
pub struct Args {
    /// Log directories or directories of logs to open (default: the bundled sample logs).
    #[arg(long, num_args = 1..)]
    logs: Vec<PathBuf>,
    /// Program files or directories of them the page offers (default: the bundled library).
    #[arg(long, num_args = 1..)]
    rules: Vec<PathBuf>,
    /// The port (0: any free one; the address is printed).
    #[arg(long, default_value_t = DEFAULT_PORT)]
    port: u16,
    /// The address to listen on. Only loopback addresses are accepted without
    /// `--expose-logs-to-network`.
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    address: IpAddr,
    /// Listen on a non-loopback `--address`: anyone who can reach it reads the open logs' tracks
    /// and maps and runs programs on this machine.
    #[arg(long)]
    expose_logs_to_network: bool,
    /// Most tuples one evaluation may hold (default: sized to the machine's memory).
    #[arg(long)]
    max_tuples: Option<u64>,
    /// Longest one evaluation may take, in milliseconds (default: 120000).
    #[arg(long)]
    timeout_ms: Option<u64>,
    /// The OpenAI-compatible LLM server that writes rules from descriptions in the page
    /// (default: $SCENALOG_LLM_BASE_URL; without either, the page offers no synthesis).
    #[arg(long, value_name = "URL")]
    base_url: Option<String>,
    /// The model's name (default: $SCENALOG_LLM_MODEL).
    #[arg(long)]
    model: Option<String>,
}

/// Runs the studio until Ctrl-C or SIGTERM: 0 on a clean stop, 2 on unusable arguments (logs,
/// rules, an address refused or taken).
pub fn run(args: Args) -> ExitCode {
    if !args.address.is_loopback() && !args.expose_logs_to_network {
        eprintln!(
            "error: --address {} is not a loopback address: anyone who can reach it would read \
             the logs and run programs here; add --expose-logs-to-network to mean it",
            args.address
        );
        return ExitCode::from(2);
    }
    let configured = args.base_url.is_some() || std::env::var_os(ENV_BASE_URL).is_some();
    let request = StudioRequest {
        logs: args.logs,
        rules: args.rules,
        limits: Limits {
            max_tuples: args.max_tuples,
            timeout_ms: args.timeout_ms,
        },
        synth: configured.then(|| SynthSettings {
            base_url: args.base_url,
            model: args.model,
            ..SynthSettings::default()
        }),
    };
    let studio = match studio::open(&request) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {}", e.render(Names::Flags));
            return ExitCode::from(2);
        }
    };
    let runtime = match tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
    {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: cannot start the server's runtime: {e}");
            return ExitCode::from(1);
        }
    };
    runtime.block_on(serve(
        studio,
        SocketAddr::new(args.address, args.port),
        args.expose_logs_to_network,
    ))
}

/// What every handler shares: the studio and the host names requests may carry.
struct Shared {
    studio: Studio,
    hosts: Vec<String>,
    any_host: bool,
}

async fn serve(studio: Studio, address: SocketAddr, exposed: bool) -> ExitCode {
    let listener = match tokio::net::TcpListener::bind(address).await {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: cannot listen on {address}: {e} (another --port?)");
            return ExitCode::from(2);
        }
    };
    let bound = match listener.local_addr() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: cannot read the address listened on: {e}");
            return ExitCode::from(1);
        }
    };
    let port = bound.port();
    let logs = studio.logs_json().as_array().map_or(0, Vec::len);
    let programs = studio.programs_json().as_array().map_or(0, Vec::len);
    let shown = match bound.ip() {
        IpAddr::V6(ip) => format!("[{ip}]"),
        IpAddr::V4(ip) => ip.to_string(),
    };
    let hosts = vec![
        format!("{shown}:{port}"),
        format!("localhost:{port}"),
        format!("127.0.0.1:{port}"),
        format!("[::1]:{port}"),
    ];
    let shared = Arc::new(Shared {
        studio,
        hosts,
        any_host: exposed,
    });
    let app = Router::new()
        .route(
            "/",
            get(|| async { page(INDEX_HTML, "text/html; charset=utf-8") }),
        )
        .route(
            "/studio.js",
            get(|| async { page(STUDIO_JS, "text/javascript; charset=utf-8") }),
        )
        .route(
            "/studio.css",
            get(|| async { page(STUDIO_CSS, "text/css; charset=utf-8") }),
        )
        .route("/api/logs", get(logs_handler))
        .route("/api/program", get(program_handler))
        .route("/api/scene", get(scene_handler))
        .route("/api/check", post(check_handler))
        .route("/api/mine", post(mine_handler))
        .route("/api/explain", post(explain_handler))
        .route("/api/synth", post(synth_handler))
        .fallback(|| async { error(StatusCode::NOT_FOUND, "no such page") })
        .layer(middleware::from_fn_with_state(shared.clone(), guard))
        .layer(DefaultBodyLimit::max(MAX_PROGRAM_BYTES + 64 * 1024))
        .with_state(shared);
    println!(
        "studio: {logs} logs, {programs} programs at http://{shown}:{port}/ (Ctrl-C stops it)"
    );
    use std::io::Write as _;
    let _ = std::io::stdout().flush();
    let served = axum::serve(listener, app)
        .with_graceful_shutdown(stop_signal())
        .await;
    match served {
        Ok(()) => {
            eprintln!("studio: stopped");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: the studio stopped: {e}");
            ExitCode::from(1)
        }
    }
}

/// Resolves on Ctrl-C or (Unix) SIGTERM.
async fn stop_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut term) => {
                tokio::select! {
                    _ = ctrl_c => {},
                    _ = term.recv() => {},
                }
            }
            Err(_) => ctrl_c.await,
        }
    }
    #[cfg(not(unix))]
    ctrl_c.await;
}

/// Refuses a request naming another host (DNS rebinding) or sent by a page of another origin.
async fn guard(State(shared): State<Arc<Shared>>, request: Request, next: Next) -> Response {
    let headers = request.headers();
    let host = headers
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .unwrap_or("");
    if !shared.any_host && !shared.hosts.iter().any(|h| h == host) {
        return error(StatusCode::FORBIDDEN, "this host name is not the studio's");
    }
    if let Some(origin) = headers.get(header::ORIGIN).and_then(|o| o.to_str().ok()) {
        let own = origin
            .strip_prefix("http://")
            .is_some_and(|rest| rest == host);
        if !own {
            return error(
                StatusCode::FORBIDDEN,
                "requests from another origin are refused",
            );
        }
    }
    let mut response = next.run(request).await;
    response.headers_mut().insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    response
}

fn page(body: &'static str, content_type: &'static str) -> Response {
    ([(header::CONTENT_TYPE, content_type)], body).into_response()
}

fn error(status: StatusCode, message: &str) -> Response {
    (status, axum::Json(json!({ "error": message }))).into_response()
}

fn answer(value: Json) -> Response {
    axum::Json(value).into_response()
}

/// Runs `work` off the server's threads (evaluations take milliseconds to seconds).
async fn blocking(
    shared: Arc<Shared>,
    work: impl FnOnce(&Studio) -> Json + Send + 'static,
) -> Response {
    match tokio::task::spawn_blocking(move || work(&shared.studio)).await {
        Ok(v) => answer(v),
        Err(_) => error(StatusCode::INTERNAL_SERVER_ERROR, "the request failed"),
    }
}

/// A JSON body of type `T`, or the error that says what is wrong with it.
fn body<T: for<'de> Deserialize<'de>>(
    headers: &HeaderMap,
    bytes: &Bytes,
) -> Result<T, (StatusCode, String)> {
    let json = headers
        .get(header::CONTENT_TYPE)
        .and_then(|c| c.to_str().ok())
        .is_some_and(|c| c.starts_with("application/json"));
    if !json {
        return Err((
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            "expected Content-Type: application/json".to_string(),
        ));
    }
    serde_json::from_slice(bytes)
        .map_err(|e| (StatusCode::BAD_REQUEST, format!("malformed request: {e}")))
}

async fn logs_handler(State(shared): State<Arc<Shared>>) -> Response {
    answer(json!({
        "logs": shared.studio.logs_json(),
        "programs": shared.studio.programs_json(),
        "synthesize": shared.studio.can_synthesize(),
    }))
}

#[derive(Deserialize)]
struct NameQuery {
    name: String,
}

async fn program_handler(
    State(shared): State<Arc<Shared>>,
    query: Result<Query<NameQuery>, axum::extract::rejection::QueryRejection>,
) -> Response {
    let Ok(Query(q)) = query else {
        return error(StatusCode::BAD_REQUEST, "expected ?name=PROGRAM");
    };
    match shared.studio.program_text(&q.name) {
        Ok(text) => answer(json!({ "name": q.name, "text": text })),
        Err(e) => error(StatusCode::NOT_FOUND, &e.render(Names::Flags)),
    }
}

#[derive(Deserialize)]
struct LogQuery {
    log: String,
}

async fn scene_handler(
    State(shared): State<Arc<Shared>>,
    query: Result<Query<LogQuery>, axum::extract::rejection::QueryRejection>,
) -> Response {
    let Ok(Query(q)) = query else {
        return error(StatusCode::BAD_REQUEST, "expected ?log=LOG_ID");
    };
    let work = shared.clone();
    match tokio::task::spawn_blocking(move || work.studio.scene_json(&q.log)).await {
        Ok(Ok(v)) => answer(v),
        Ok(Err(e)) => error(StatusCode::NOT_FOUND, &e.render(Names::Flags)),
        Err(_) => error(StatusCode::INTERNAL_SERVER_ERROR, "the request failed"),
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ProgramBody {
    text: String,
}

async fn check_handler(headers: HeaderMap, bytes: Bytes) -> Response {
    match body::<ProgramBody>(&headers, &bytes) {
        Ok(b) => answer(json!({ "diagnostics": studio::check_json(&b.text) })),
        Err((status, message)) => error(status, &message),
    }
}

async fn mine_handler(
    State(shared): State<Arc<Shared>>,
    headers: HeaderMap,
    bytes: Bytes,
) -> Response {
    match body::<ProgramBody>(&headers, &bytes) {
        Ok(b) => blocking(shared, move |s| s.mine_json(&b.text)).await,
        Err((status, message)) => error(status, &message),
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ExplainBody {
    text: String,
    log: String,
    track: String,
    frame: u32,
}

async fn explain_handler(
    State(shared): State<Arc<Shared>>,
    headers: HeaderMap,
    bytes: Bytes,
) -> Response {
    match body::<ExplainBody>(&headers, &bytes) {
        Ok(b) => {
            blocking(shared, move |s| {
                s.explain_json(&b.text, &b.log, &b.track, b.frame)
            })
            .await
        }
        Err((status, message)) => error(status, &message),
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DescriptionBody {
    description: String,
}

async fn synth_handler(
    State(shared): State<Arc<Shared>>,
    headers: HeaderMap,
    bytes: Bytes,
) -> Response {
    match body::<DescriptionBody>(&headers, &bytes) {
        Ok(b) => blocking(shared, move |s| s.synthesize_json(&b.description)).await,
        Err((status, message)) => error(status, &message),
    }
}
