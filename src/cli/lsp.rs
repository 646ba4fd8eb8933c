//! `scenalog lsp`: a Language Server Protocol server over standard input and output, for editors
//! (VS Code, Neovim, Helix…) editing `.dl` programs. It keeps the open documents' text and answers
//! from [`crate::api::editor`]: the checker's diagnostics on open and on every change, the
//! catalog's documentation (or a variable's type) on hover, relation names and closed values on
//! completion, the fixes the diagnostics carry as quick-fix code actions, the definition of a
//! relation (the program's rules, the prelude's declaration) and a variable, references, rename
//! and the outline of the program's rules. The protocol (framing, JSON-RPC,
//! types) is `lsp-server` and `lsp-types`; this module only maps between them and the API.

use std::collections::HashMap;
use std::process::ExitCode;

use lsp_server::{Connection, ErrorCode, Message, Notification, Request, RequestId, Response};
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, Notification as _,
    PublishDiagnostics,
};
use lsp_types::request::{
    CodeActionRequest, Completion, DocumentSymbolRequest, GotoDefinition, HoverRequest, References,
    Rename, Request as _,
};
use lsp_types::{
    CodeAction, CodeActionKind, CodeActionOrCommand, CodeActionParams,
    CodeActionProviderCapability, CompletionItem, CompletionItemKind, CompletionOptions,
    CompletionParams, CompletionResponse, Diagnostic, DiagnosticRelatedInformation,
    DiagnosticSeverity, DocumentSymbolParams, DocumentSymbolResponse, Documentation,
    GotoDefinitionParams, GotoDefinitionResponse, HoverContents, HoverParams,
    HoverProviderCapability, InsertTextFormat, Location, MarkupContent, MarkupKind, NumberOrString,
    OneOf, PublishDiagnosticsParams, ReferenceParams, RenameParams, ServerCapabilities,
    SymbolInformation, SymbolKind, TextDocumentSyncCapability, TextDocumentSyncKind, TextEdit, Uri,
    WorkspaceEdit,
};

use crate::api::editor::{self, CompletionKind, EditorDiagnostic, Level};

/// Arguments of `scenalog lsp` (none: it speaks over standard input and output).
#[derive(clap::Args)]
pub struct Args {
    /// Accepted and ignored: editors' LSP clients pass it to say the transport.
    #[arg(long)]
    pub stdio: bool,
}

/// Serves one client until it asks to shut down and exit (exit 0), or its input ends.
pub fn run(_args: Args) -> ExitCode {
    let (connection, io_threads) = Connection::stdio();
    let served = serve(&connection);
    drop(connection);
    let joined = io_threads.join();
    match (served, joined) {
        (Ok(()), Ok(())) => ExitCode::SUCCESS,
        (Err(e), _) => {
            eprintln!("scenalog lsp: {e}");
            ExitCode::FAILURE
        }
        (_, Err(e)) => {
            eprintln!("scenalog lsp: {e}");
            ExitCode::FAILURE
        }
    }
}

/// What the server can do, as `initialize` answers.
fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some(vec!["\"".into(), "(".into()]),
            ..CompletionOptions::default()
        }),
        code_action_provider: Some(CodeActionProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        rename_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        ..ServerCapabilities::default()
    }
}

/// The initialisation handshake, then the message loop.
fn serve(connection: &Connection) -> Result<(), String> {
    let caps = serde_json::to_value(capabilities()).map_err(|e| e.to_string())?;
    let info = serde_json::json!({
        "capabilities": caps,
        "serverInfo": { "name": "scenalog", "version": env!("CARGO_PKG_VERSION") },
    });
    let (id, _params) = connection
        .initialize_start()
        .map_err(|e| format!("initialize: {e}"))?;
    connection
        .initialize_finish(id, info)
        .map_err(|e| format!("initialize: {e}"))?;
    // Keyed by the URI's text: `Uri` caches its parts inside, which a hash key must not.
    let mut docs: HashMap<String, String> = HashMap::new();
    for msg in &connection.receiver {
        match msg {
            Message::Request(req) => {
                if connection
                    .handle_shutdown(&req)
                    .map_err(|e| format!("shutdown: {e}"))?
                {
                    return Ok(());
                }
                let response = answer(&docs, req);
                send(connection, Message::Response(response))?;
            }
            Message::Notification(n) => {
                if let Some(uri) = update(&mut docs, n) {
                    publish(connection, &docs, uri)?;
                }
            }
            Message::Response(_) => {}
        }
    }
    Ok(())
}

fn send(connection: &Connection, msg: Message) -> Result<(), String> {
    connection
        .sender
        .send(msg)
        .map_err(|e| format!("the client went away: {e}"))
}

/// Applies a document notification; the document whose diagnostics changed, if any.
fn update(docs: &mut HashMap<String, String>, n: Notification) -> Option<Uri> {
    match n.method.as_str() {
        DidOpenTextDocument::METHOD => {
            let p: lsp_types::DidOpenTextDocumentParams = serde_json::from_value(n.params).ok()?;
            docs.insert(
                p.text_document.uri.as_str().to_string(),
                p.text_document.text,
            );
            Some(p.text_document.uri)
        }
        DidChangeTextDocument::METHOD => {
            let p: lsp_types::DidChangeTextDocumentParams =
                serde_json::from_value(n.params).ok()?;
            // Full synchronisation: the last change holds the whole text.
            let text = p.content_changes.into_iter().last()?.text;
            docs.insert(p.text_document.uri.as_str().to_string(), text);
            Some(p.text_document.uri)
        }
        DidCloseTextDocument::METHOD => {
            let p: lsp_types::DidCloseTextDocumentParams = serde_json::from_value(n.params).ok()?;
            docs.remove(p.text_document.uri.as_str());
            None
        }
        _ => None,
    }
}

/// Sends the diagnostics of document `uri`.
fn publish(
    connection: &Connection,
    docs: &HashMap<String, String>,
    uri: Uri,
) -> Result<(), String> {
    let text = text_of(docs, &uri);
    let diagnostics = editor::diagnostics(text)
        .iter()
        .map(|d| to_lsp(&uri, d))
        .collect();
    let params = PublishDiagnosticsParams {
        uri,
        diagnostics,
        version: None,
    };
    let params = serde_json::to_value(params).map_err(|e| e.to_string())?;
    send(
        connection,
        Message::Notification(Notification::new(
            PublishDiagnostics::METHOD.to_string(),
            params,
        )),
    )
}

fn position(p: editor::Position) -> lsp_types::Position {
    lsp_types::Position::new(p.line, p.character)
}

fn range(r: editor::Range) -> lsp_types::Range {
    lsp_types::Range::new(position(r.start), position(r.end))
}

fn from_lsp(p: lsp_types::Position) -> editor::Position {
    editor::Position {
        line: p.line,
        character: p.character,
    }
}

fn to_lsp(uri: &Uri, d: &EditorDiagnostic) -> Diagnostic {
    let related = d
        .related
        .iter()
        .map(|(r, label)| DiagnosticRelatedInformation {
            location: Location::new(uri.clone(), range(*r)),
            message: label.clone(),
        })
        .collect::<Vec<_>>();
    Diagnostic {
        range: range(d.range),
        severity: Some(match d.level {
            Level::Error => DiagnosticSeverity::ERROR,
            Level::Warning => DiagnosticSeverity::WARNING,
        }),
        code: Some(NumberOrString::String(d.code.clone())),
        source: Some("scenalog".into()),
        message: d.message.clone(),
        related_information: (!related.is_empty()).then_some(related),
        ..Diagnostic::default()
    }
}

/// The response to a request: hover, completion and code actions; any other method is a
/// `MethodNotFound` error and malformed parameters an `InvalidParams` error.
fn answer(docs: &HashMap<String, String>, req: Request) -> Response {
    let id = req.id.clone();
    let result = match req.method.as_str() {
        HoverRequest::METHOD => params::<HoverParams>(&req).map(|p| {
            let doc = &p.text_document_position_params;
            let text = text_of(docs, &doc.text_document.uri);
            let found = editor::hover(text, from_lsp(doc.position));
            serde_json::to_value(found.map(|h| lsp_types::Hover {
                contents: HoverContents::Markup(MarkupContent {
                    kind: MarkupKind::Markdown,
                    value: h.markdown,
                }),
                range: Some(range(h.range)),
            }))
        }),
        Completion::METHOD => params::<CompletionParams>(&req).map(|p| {
            let doc = &p.text_document_position;
            let text = text_of(docs, &doc.text_document.uri);
            let items: Vec<CompletionItem> = editor::completions(text, from_lsp(doc.position))
                .into_iter()
                .map(completion_item)
                .collect();
            serde_json::to_value(CompletionResponse::Array(items))
        }),
        CodeActionRequest::METHOD => params::<CodeActionParams>(&req).map(|p| {
            let uri = p.text_document.uri.clone();
            let text = text_of(docs, &uri);
            serde_json::to_value(code_actions(&uri, text, p.range))
        }),
        GotoDefinition::METHOD => params::<GotoDefinitionParams>(&req).map(|p| {
            let doc = &p.text_document_position_params;
            let uri = doc.text_document.uri.clone();
            let text = text_of(docs, &uri);
            let found = editor::definition(text, from_lsp(doc.position));
            serde_json::to_value(found.and_then(|d| definition_response(&uri, d)))
        }),
        References::METHOD => params::<ReferenceParams>(&req).map(|p| {
            let doc = &p.text_document_position;
            let uri = doc.text_document.uri.clone();
            let text = text_of(docs, &uri);
            let found: Vec<Location> = editor::references(text, from_lsp(doc.position))
                .into_iter()
                .map(|r| Location::new(uri.clone(), range(r)))
                .collect();
            serde_json::to_value(found)
        }),
        Rename::METHOD => match params::<RenameParams>(&req) {
            Ok(p) => {
                let doc = &p.text_document_position;
                let uri = doc.text_document.uri.clone();
                let text = text_of(docs, &uri);
                match editor::rename(text, from_lsp(doc.position), &p.new_name) {
                    Ok(edits) => Ok(serde_json::to_value(workspace_edit(&uri, &edits))),
                    Err(why) => Err(error(id.clone(), ErrorCode::InvalidRequest, why)),
                }
            }
            Err(e) => Err(e),
        },
        DocumentSymbolRequest::METHOD => params::<DocumentSymbolParams>(&req).map(|p| {
            let uri = p.text_document.uri.clone();
            let text = text_of(docs, &uri);
            #[allow(deprecated)] // `deprecated` is a field every constructor must fill.
            let found: Vec<SymbolInformation> = editor::symbols(text)
                .into_iter()
                .map(|s| SymbolInformation {
                    name: s.name,
                    kind: SymbolKind::FUNCTION,
                    tags: None,
                    deprecated: None,
                    location: Location::new(uri.clone(), range(s.range)),
                    container_name: None,
                })
                .collect();
            serde_json::to_value(DocumentSymbolResponse::Flat(found))
        }),
        other => Err(error(
            id.clone(),
            ErrorCode::MethodNotFound,
            format!("scenalog lsp does not answer `{other}`"),
        )),
    };
    match result {
        Ok(Ok(value)) => Response::new_ok(id, value),
        Ok(Err(e)) => error(id, ErrorCode::InternalError, e.to_string()),
        Err(e) => e,
    }
}

fn error(id: RequestId, code: ErrorCode, message: String) -> Response {
    Response::new_err(id, code as i32, message)
}

/// A request's parameters, or the `InvalidParams` response saying why they do not fit.
fn params<P: serde::de::DeserializeOwned>(req: &Request) -> Result<P, Response> {
    serde_json::from_value(req.params.clone()).map_err(|e| {
        error(
            req.id.clone(),
            ErrorCode::InvalidParams,
            format!("malformed `{}` parameters: {e}", req.method),
        )
    })
}

/// The text of an open document (empty for one never opened).
fn text_of<'a>(docs: &'a HashMap<String, String>, uri: &Uri) -> &'a str {
    docs.get(uri.as_str())
        .map(String::as_str)
        .unwrap_or_default()
}

fn completion_item(c: editor::Completion) -> CompletionItem {
    CompletionItem {
        label: c.label,
        kind: Some(match c.kind {
            CompletionKind::Relation => CompletionItemKind::FUNCTION,
            CompletionKind::Concept => CompletionItemKind::INTERFACE,
            CompletionKind::Helper => CompletionItemKind::METHOD,
            CompletionKind::Value => CompletionItemKind::ENUM_MEMBER,
        }),
        detail: Some(c.detail),
        documentation: (!c.documentation.is_empty())
            .then_some(Documentation::String(c.documentation)),
        insert_text: Some(c.insert_text),
        insert_text_format: Some(if c.kind == CompletionKind::Value {
            InsertTextFormat::PLAIN_TEXT
        } else {
            InsertTextFormat::SNIPPET
        }),
        ..CompletionItem::default()
    }
}

/// A definition as a location: in the document, or in the prelude's file when the source tree
/// is there.
fn definition_response(uri: &Uri, d: editor::Definition) -> Option<GotoDefinitionResponse> {
    match d {
        editor::Definition::Here(ranges) => Some(GotoDefinitionResponse::Array(
            ranges
                .into_iter()
                .map(|r| Location::new(uri.clone(), range(r)))
                .collect(),
        )),
        editor::Definition::Prelude(r) => {
            let path = editor::prelude_file()?;
            let file: Uri = format!("file://{}", path.display()).parse().ok()?;
            Some(GotoDefinitionResponse::Scalar(Location::new(
                file,
                range(r),
            )))
        }
    }
}

/// Edits of one document as a workspace edit.
// `WorkspaceEdit` keys its changes by `Uri`, as lsp-types has it.
#[allow(clippy::mutable_key_type)]
fn workspace_edit(uri: &Uri, edits: &[editor::TextEdit]) -> WorkspaceEdit {
    let edits = edits
        .iter()
        .map(|e| TextEdit::new(range(e.range), e.new_text.clone()))
        .collect();
    WorkspaceEdit::new(HashMap::from([(uri.clone(), edits)]))
}

/// A quick fix for every diagnostic with a fix whose range meets `at`.
fn code_actions(uri: &Uri, text: &str, at: lsp_types::Range) -> Vec<CodeActionOrCommand> {
    let meets = |r: editor::Range| {
        let r = range(r);
        r.start <= at.end && at.start <= r.end
    };
    editor::diagnostics(text)
        .iter()
        .filter(|d| !d.fix.is_empty() && meets(d.range))
        .map(|d| {
            let title = d.hint.clone().unwrap_or_else(|| format!("fix {}", d.code));
            CodeActionOrCommand::CodeAction(CodeAction {
                title,
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: Some(vec![to_lsp(uri, d)]),
                edit: Some(workspace_edit(uri, &d.fix)),
                is_preferred: Some(true),
                ..CodeAction::default()
            })
        })
        .collect()
}
