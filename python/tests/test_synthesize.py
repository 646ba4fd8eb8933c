"""``scenalog.synthesize`` against a scripted local OpenAI-compatible server (127.0.0.1, one
thread, stopped after the test): candidates run on the sample logs, the majority's meaning
kept, the evidence round asked, and an unreachable server an error."""

import json
import threading
from http.server import BaseHTTPRequestHandler, HTTPServer

import pytest

import scenalog

from conftest import LOGS

GOOD = 'referred(V, T) :- category(V, "VEHICLE"), turning(V, T, "left").'
SWAPPED = 'referred(X, T) :- turning(X, T, "left"), category(X, "VEHICLE").'
MINORITY = 'referred(V, T) :- category(V, "REGULAR_VEHICLE"), turning(V, T, "right").'


class Scripted:
    """A server answering the i-th chat completion with ``replies[i]``."""

    def __init__(self, replies):
        self.replies = list(replies)
        self.requests = []
        outer = self

        class Handler(BaseHTTPRequestHandler):
            def do_POST(self):
                body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
                outer.requests.append(body)
                i = len(outer.requests) - 1
                text = outer.replies[i] if i < len(outer.replies) else "no more answers"
                answer = json.dumps(
                    {
                        "choices": [{"message": {"role": "assistant", "content": text}}],
                        "usage": {"prompt_tokens": 100, "completion_tokens": 10, "total_tokens": 110},
                    }
                ).encode()
                self.send_response(200)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(answer)))
                self.end_headers()
                self.wfile.write(answer)

            def log_message(self, *args):
                pass

        self.server = HTTPServer(("127.0.0.1", 0), Handler)
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    @property
    def url(self):
        return f"http://127.0.0.1:{self.server.server_address[1]}/v1"

    def close(self):
        self.server.shutdown()
        self.server.server_close()


def fenced(program):
    return f"```scenalog\n{program}\n```"


def test_candidates_keep_the_majority_and_show_the_model_its_matches():
    server = Scripted([fenced(MINORITY), fenced(GOOD), fenced(SWAPPED), "KEEP"])
    try:
        s = scenalog.synthesize(
            "vehicle making a left turn", candidates=3, logs=LOGS, base_url=server.url
        )
    finally:
        server.close()
    assert s.clean
    assert s.program == f"// description: vehicle making a left turn\n{GOOD}\n"
    assert len(s.candidates) == 3
    assert s.transcript["search"]["chosen"] == 1
    assert s.candidates[1]["group"] == [1, 2]
    assert s.transcript["evidence"][0]["verdict"] == "keep"
    shown = server.requests[3]["messages"][-1]["content"]
    assert "On the 3 logs your program matches" in shown
    assert s.usage["prompt_tokens"] == 400
    # One candidate asks once, as before.
    server = Scripted([fenced(GOOD)])
    try:
        one = scenalog.synthesize("vehicle making a left turn", base_url=server.url)
    finally:
        server.close()
    assert one.clean and one.candidates == [] and "evidence" not in one.transcript
    assert len(server.requests) == 1


def test_the_grammar_goes_in_the_servers_field():
    server = Scripted([fenced(GOOD)])
    try:
        scenalog.synthesize("vehicle making a left turn", base_url=server.url, grammar="vllm")
    finally:
        server.close()
    assert "root ::=" in server.requests[0]["structured_outputs"]["grammar"]
    with pytest.raises(ValueError, match="grammar"):
        scenalog.synthesize("x", base_url="http://127.0.0.1:9/v1", grammar="openai")


def test_an_unreachable_server_is_an_error():
    with pytest.raises(scenalog.ScenalogError):
        scenalog.synthesize("x", base_url="http://127.0.0.1:9/v1", retries=0, timeout_s=2)
