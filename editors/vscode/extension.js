// Starts `scenalog lsp` for `.dl` files: everything else (diagnostics, hover, completion, quick
// fixes, definitions, rename) comes from the server.
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const command = vscode.workspace.getConfiguration("scenalog").get("path") || "scenalog";
  const server = { command, args: ["lsp"] };
  client = new LanguageClient(
    "scenalog",
    "Scenalog",
    { run: server, debug: server },
    { documentSelector: [{ scheme: "file", language: "scenalog" }] }
  );
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
