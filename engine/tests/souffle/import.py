#!/usr/bin/env python3
"""Builds the conformance cases in `cases/` from Soufflé's own tests.

Usage: import.py SOUFFLE_CHECKOUT [COMMIT]

Reads tests/evaluation, tests/semantic and tests/example of a Soufflé checkout (at COMMIT, by
`git show`, default HEAD), translates each test whose features are in Scenalog's language, and
writes per test `cases/SUITE/NAME/program.dl` (facts of `.input` relations inlined) with the
expected outputs Soufflé's test carries (`REL.csv`, or `rejected` for a test Soufflé refuses).
Tests that use a feature Scenalog lacks are listed in `excluded.tsv` with the feature. The
translation is mechanical, so it can be rerun on a newer Soufflé:

- every relation `r` becomes `s_r` (Soufflé capitalises relations and may use Scenalog's catalog
  names) and every variable `v` becomes `Vv` (Soufflé's variables may be lowercase);
- types: number and unsigned to int, float to float, symbol to str, through `.type` aliases;
- `%` becomes `mod` (in Scenalog `%` starts a comment), hex and binary literals decimal;
- an aggregate over one atom without braces (`min x : a(x)`) gets braces;
- directives Scenalog has no need of (`.input`, `.output`, `.pragma`, `.plan`) are dropped.
"""

import os
import re
import subprocess
import sys

SUITES = ["evaluation", "semantic", "example"]
# Largest program (facts inlined) kept in the repository.
MAX_PROGRAM_BYTES = 400_000

TOKEN = re.compile(
    r"""
    (?P<ws>\s+)
  | (?P<comment>//[^\n]*|/\*.*?\*/)
  | (?P<string>"(?:\\.|[^"\\\n])*")
  | (?P<number>0x[0-9a-fA-F]+|0b[01]+|\d+\.\d+(?:[eE][-+]?\d+)?|\d+[eE][-+]?\d+|\d+u?)
  | (?P<ident>[A-Za-z_?][A-Za-z0-9_?]*)
  | (?P<punct>:-|<=|>=|!=|<:|::|[-+*/%^(){}\[\],.:;=<>!$@#|&~])
    """,
    re.S | re.X,
)

AGGREGATES = {"count", "sum", "min", "max"}
UNSUPPORTED_AGGREGATES = {"mean", "range"}
FUNCTORS = {"abs": "abs", "min": "min", "max": "max"}
UNSUPPORTED_WORDS = {
    "band": "bitwise operators",
    "bor": "bitwise operators",
    "bxor": "bitwise operators",
    "bnot": "bitwise operators",
    "bshl": "bitwise operators",
    "bshr": "bitwise operators",
    "bshru": "bitwise operators",
    "land": "logical operators on numbers",
    "lor": "logical operators on numbers",
    "lxor": "logical operators on numbers",
    "lnot": "logical operators on numbers",
    "nil": "records",
    "as": "type casts",
    "true": "the constants true and false",
    "false": "the constants true and false",
    "match": "string functors",
    "contains": "string functors",
    "cat": "string functors",
    "strlen": "string functors",
    "substr": "string functors",
    "ord": "string functors",
    "to_number": "conversion functors",
    "to_string": "conversion functors",
    "to_float": "conversion functors",
    "to_unsigned": "conversion functors",
    "itof": "conversion functors",
    "itou": "conversion functors",
    "ftoi": "conversion functors",
    "ftou": "conversion functors",
    "utoi": "conversion functors",
    "utof": "conversion functors",
    "autoinc": "autoinc()",
    "choice": "choice domains",
    "choice-domain": "choice domains",
}
BASE_TYPES = {"number": "int", "unsigned": "int", "float": "float", "symbol": "str"}
UNSUPPORTED_DIRECTIVES = {
    "comp": "components",
    "init": "components",
    "override": "components",
    "functor": "user-defined functors",
    "limitsize": ".limitsize",
    "include": ".include",
    "once": ".once",
}


# Errors of Soufflé's that are about something Scenalog's language does not have: a test that
# expects one of them is excluded, not counted as a program Scenalog must refuse.
OUTSIDE_THE_LANGUAGE = [
    (r"Redefinition of type|subtype|declared type|[Tt]ype .* (is not|not) ", "Soufflé's type declarations"),
    (r"Undefined relation", "relations used without .decl (Scenalog infers their types)"),
    (r"[Ii]nline", "Soufflé's rules for inline relations"),
    (r"[Pp]lan", ".plan directives (Scenalog plans joins itself)"),
]


class Unsupported(Exception):
    """A feature Scenalog's language lacks."""


def tokens(text):
    pos, out = 0, []
    while pos < len(text):
        m = TOKEN.match(text, pos)
        if not m:
            raise Unsupported(f"unreadable text {text[pos:pos + 20]!r}")
        kind = m.lastgroup
        if kind not in ("ws", "comment"):
            out.append((kind, m.group()))
        pos = m.end()
    return out


def group_end(toks, i):
    """The index after the bracketed group opening at `toks[i]`."""
    depth = 0
    while i < len(toks):
        t = toks[i][1]
        if t in "([{":
            depth += 1
        elif t in ")]}":
            depth -= 1
            if depth == 0:
                return i + 1
        i += 1
    raise Unsupported("an unclosed bracket")


def directive_end(name, toks, i):
    """Where the directive `.name` whose arguments start at `toks[i]` ends (directives have no
    final `.`: the next statement starts where its arguments stop)."""
    n = len(toks)
    at = lambda j: toks[j][1] if j < n else None
    if name in UNSUPPORTED_DIRECTIVES:
        raise Unsupported(UNSUPPORTED_DIRECTIVES[name])
    if name in ("decl", "input", "output", "printsize"):
        while i < n and toks[i][0] == "ident":
            i += 1
            if at(i) == "(":
                i = group_end(toks, i)
            # `.decl` qualifiers: names not followed by `(` (btree, brie, eqrel, inline, ...).
            while name == "decl" and i < n and toks[i][0] == "ident" and at(i + 1) != "(" and at(i + 1) != ":-":
                if toks[i][1] in ("eqrel",):
                    raise Unsupported("eqrel relations")
                if toks[i][1] in ("choice", "choice-domain"):
                    raise Unsupported("choice domains")
                i += 1
            if at(i) == "," and i + 1 < n and toks[i + 1][0] == "ident":
                i += 1
                continue
            break
        return i
    if name in ("number_type", "symbol_type"):
        return i + 1
    if name == "type":
        i += 1  # the name
        if at(i) not in ("<:", "="):
            raise Unsupported("a .type form")
        i += 1
        while i < n:
            if at(i) in ("[", "{"):
                raise Unsupported("records or algebraic data types")
            if toks[i][0] != "ident" or at(i + 1) == "(":
                raise Unsupported("a .type form")
            i += 1
            if at(i) in ("[", "{"):
                raise Unsupported("records or algebraic data types")
            if at(i) == "|":
                i += 1
                continue
            return i
        return i
    if name == "pragma":
        while i < n and toks[i][0] == "string":
            i += 1
        return i
    if name == "plan":
        while i < n and (toks[i][0] == "number" or at(i) in (":", ",")):
            i += 1
            if at(i) == "(":
                i = group_end(toks, i)
        return i
    raise Unsupported(f"the directive .{name}")


def statements(toks):
    """Directives (a `.name` and its arguments) and clauses (up to their final `.`)."""
    out, i, n = [], 0, len(toks)
    while i < n:
        if toks[i][1] == "." and i + 1 < n and toks[i + 1][0] == "ident":
            name = toks[i + 1][1]
            end = directive_end(name, toks, i + 2)
            out.append([("directive", name)] + toks[i + 2:end])
            i = end
            continue
        j, depth = i, 0
        while j < n:
            t = toks[j][1]
            if t in "([{":
                depth += 1
            elif t in ")]}":
                depth -= 1
            elif t == "." and depth == 0:
                break
            j += 1
        if j >= n:
            raise Unsupported("a clause without a final `.`")
        out.append(toks[i:j])
        i = j + 1
    return out


class Program:
    def __init__(self):
        self.types = {}  # alias -> base
        self.decls = {}  # name -> [(col, type)]
        self.qualifiers = {}
        self.inputs = {}  # name -> params
        self.outputs = {}  # name -> params
        self.clauses = []  # token lists
        self.duplicates = []  # relations declared twice
        self.printsizes = []  # relations whose size Soufflé prints

    def base(self, t):
        seen = set()
        while t in self.types and t not in seen:
            seen.add(t)
            t = self.types[t]
        if t not in BASE_TYPES:
            raise Unsupported(f"the type `{t}`")
        return BASE_TYPES[t]


def params(toks):
    """`(IO=file, filename="x")` to a dict."""
    out, i = {}, 0
    while i < len(toks):
        if toks[i][0] == "ident" and i + 2 < len(toks) and toks[i + 1][1] == "=":
            v = toks[i + 2][1]
            out[toks[i][1]] = v[1:-1] if v.startswith('"') else v
            i += 3
        else:
            i += 1
    return out


def read_directive(p, s):
    name, body = s[0][1], s[1:]
    if name in UNSUPPORTED_DIRECTIVES:
        raise Unsupported(UNSUPPORTED_DIRECTIVES[name])
    if name in ("pragma", "plan"):
        return
    if name in ("number_type", "symbol_type"):
        p.types[body[0][1]] = "number" if name == "number_type" else "symbol"
        return
    if name == "type":
        texts = [t for _, t in body]
        if len(texts) == 3 and texts[1] in ("<:", "="):
            p.types[texts[0]] = texts[2]
            return
        if len(texts) >= 3 and texts[1] == "=" and all(
            t == "|" for t in texts[3::2]
        ) and all(k == "ident" for k, _ in body[2::2]):
            # A union of types: fine when they all have one base type.
            bases = {p.base(t) for t in texts[2::2]}
            if len(bases) != 1:
                raise Unsupported("union types of different base types")
            p.types[texts[0]] = {v: k for k, v in BASE_TYPES.items()}[bases.pop()]
            return
        raise Unsupported("records or algebraic data types")
    if name == "decl":
        i = 0
        names = []
        while i < len(body) and body[i][0] == "ident":
            names.append(body[i][1])
            i += 1
            if i < len(body) and body[i][1] == ",":
                i += 1
        if i >= len(body) or body[i][1] != "(":
            raise Unsupported("a .decl form")
        j = group_end(body, i) - 1
        inner, quals = body[i + 1:j], [t for _, t in body[j + 1:]]
        for q in quals:
            if q in ("eqrel",):
                raise Unsupported("eqrel relations")
            if q in ("choice", "choice-domain"):
                raise Unsupported("choice domains")
        cols, k = [], 0
        while k < len(inner):
            if inner[k][0] != "ident" or k + 2 >= len(inner) or inner[k + 1][1] != ":":
                raise Unsupported("a .decl column form")
            col, ty = inner[k][1], inner[k + 2][1]
            k += 3
            if k < len(inner) and inner[k][1] == ",":
                k += 1
            elif k < len(inner):
                raise Unsupported("a .decl column type form")
            cols.append((col, ty))
        for n in names:
            if n in p.decls:
                p.duplicates.append(n)
            p.decls[n] = cols
        return
    if name == "printsize":
        p.printsizes.extend(t for k, t in body if k == "ident")
        return
    if name in ("input", "output"):
        i = 0
        while i < len(body):
            if body[i][0] != "ident":
                i += 1
                continue
            rel = body[i][1]
            j = i + 1
            ps = {}
            if j < len(body) and body[j][1] == "(":
                k = group_end(body, j) - 1
                ps = params(body[j + 1:k])
                j = k + 1
            (p.inputs if name == "input" else p.outputs).setdefault(rel, ps)
            i = j
        return
    raise Unsupported(f"the directive .{name}")


def translate_clause(p, toks):
    """One Soufflé clause to Scenalog text (one clause per head)."""
    for kind, t in toks:
        if kind == "ident" and t in UNSUPPORTED_WORDS:
            raise Unsupported(UNSUPPORTED_WORDS[t])
        if kind == "ident" and t in UNSUPPORTED_AGGREGATES:
            raise Unsupported(f"the aggregate {t}")
        if t in ("[", "]", "$", "@", "#", "|", "&", "~", ";", "::", "<:"):
            raise Unsupported({"[": "records", "]": "records", "$": "algebraic data types",
                               "@": "user-defined functors", ";": "disjunction in a body",
                               "::": "components"}.get(t, f"the token {t}"))
    # Split heads from the body.
    if any(t == ":-" for _, t in toks):
        at = [t for _, t in toks].index(":-")
        heads, body = toks[:at], toks[at + 1:]
    else:
        heads, body = toks, None
    if any(t == "<=" for _, t in heads):
        raise Unsupported("subsumption")
    if body is not None:
        body = unparenthesise_targets(body)
        for lit in split_top(body, ","):
            check_aggregate_place(lit)
    if any(is_aggregate(heads, k) for k in range(len(heads))):
        raise Unsupported("aggregates inside expressions or atom arguments")
    head_atoms = split_top(heads, ",")
    out = []
    body_text = render(p, body) if body is not None else None
    for h in head_atoms:
        ht = render(p, h)
        out.append(f"{ht} :- {body_text}." if body_text is not None else f"{ht}.")
    return out


def is_aggregate(toks, i):
    """Whether `toks[i]` is an aggregate keyword (not the functor `min(a, b)`)."""
    kind, t = toks[i]
    if kind != "ident" or t not in AGGREGATES:
        return False
    if i + 1 < len(toks) and toks[i + 1][1] == "(":
        # `max (x / y) : ...`: a parenthesised target, if a `:` follows the group.
        end = group_end(toks, i + 1)
        return end < len(toks) and toks[end][1] == ":"
    return True


def unparenthesise_targets(toks):
    """`max (x / y) : {...}` to `max x / y : {...}`."""
    toks = list(toks)
    i = 0
    while i < len(toks):
        if is_aggregate(toks, i) and i + 1 < len(toks) and toks[i + 1][1] == "(":
            end = group_end(toks, i + 1)
            toks = toks[:i + 1] + toks[i + 2:end - 1] + toks[end:]
        i += 1
    return toks


def check_aggregate_place(lit):
    """Scenalog writes an aggregate as a literal of its own, `V = agg ... : { ... }`, in a body
    or in an aggregate's braces."""
    lit = brace_aggregates(lit)
    for i in range(len(lit)):
        if is_aggregate(lit, i):
            if not (i == 2 and lit[0][0] in ("ident",) and lit[1][1] == "="):
                raise Unsupported("aggregates inside expressions or atom arguments")
            # The braces' literals, then nothing after them.
            j = next((k for k in range(i, len(lit)) if lit[k][1] == "{"), None)
            if j is None:
                raise Unsupported("an aggregate form")
            end = group_end(lit, j)
            for inner in split_top(lit[j + 1:end - 1], ","):
                check_aggregate_place(inner)
            if any(is_aggregate(lit, k) for k in range(i + 1, j)) or end != len(lit):
                raise Unsupported("aggregates inside expressions or atom arguments")
            return


def split_top(toks, sep):
    parts, cur, depth = [], [], 0
    for k, t in toks:
        if t in "([{":
            depth += 1
        elif t in ")]}":
            depth -= 1
        if t == sep and depth == 0:
            parts.append(cur)
            cur = []
        else:
            cur.append((k, t))
    parts.append(cur)
    return parts


def render(p, toks):
    toks = brace_aggregates(toks)
    out = []
    for i, (kind, t) in enumerate(toks):
        nxt = toks[i + 1][1] if i + 1 < len(toks) else None
        if kind == "ident":
            if nxt == "(" and t in FUNCTORS and not is_relation(p, t):
                out.append(FUNCTORS[t])
            elif nxt == "(":
                out.append("s_" + t)
            elif t in AGGREGATES:
                out.append(t)
            elif t == "_":
                out.append("_")
            else:
                out.append("V" + t.replace("?", "Q"))
        elif kind == "number":
            out.append(number(t))
        elif t == "%":
            out.append("mod")
        else:
            out.append(t)
    text = ""
    for piece in out:
        if text and needs_space(text[-1], piece[0]):
            text += " "
        text += piece
    return text


def needs_space(a, b):
    return (a.isalnum() or a in "_\"") and (b.isalnum() or b in "_\"")


def is_relation(p, name):
    return name in p.decls


def number(t):
    if t.startswith("0x"):
        return str(int(t, 16))
    if t.startswith("0b"):
        return str(int(t, 2))
    if t.endswith("u"):
        return t[:-1]
    return t


def brace_aggregates(toks):
    """`count : a(x)` and `min x : a(x)` (one atom, no braces) get braces."""
    toks = list(toks)
    i = 0
    while i < len(toks):
        kind, t = toks[i]
        if kind == "ident" and t in AGGREGATES and not (i + 1 < len(toks) and toks[i + 1][1] == "("):
            # Find the `:` of this aggregate at depth 0.
            j, depth = i + 1, 0
            while j < len(toks):
                if toks[j][1] in "([{":
                    depth += 1
                elif toks[j][1] in ")]}":
                    depth -= 1
                if toks[j][1] == ":" and depth == 0:
                    break
                j += 1
            if j + 1 < len(toks) and toks[j + 1][1] != "{":
                # One atom, maybe negated: `!`? name ( ... ).
                k = j + 1
                if toks[k][1] == "!":
                    k += 1
                if k + 1 < len(toks) and toks[k][0] == "ident" and toks[k + 1][1] == "(":
                    d, m = 0, k + 1
                    while m < len(toks):
                        if toks[m][1] == "(":
                            d += 1
                        elif toks[m][1] == ")":
                            d -= 1
                            if d == 0:
                                break
                        m += 1
                    toks = toks[:j + 1] + [("punct", "{")] + toks[j + 1:m + 1] + [("punct", "}")] + toks[m + 1:]
        i += 1
    return toks


def fact_value(v, ty):
    if ty == "str":
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if ty == "int":
        v = v.strip()
        if re.fullmatch(r"-?0x[0-9a-fA-F]+", v):
            return str(int(v, 16))
        if re.fullmatch(r"-?0b[01]+", v):
            return str(int(v, 2))
        if not re.fullmatch(r"-?\d+", v):
            raise Unsupported(f"a number fact {v!r}")
        return v
    v = v.strip()
    try:
        float(v)
    except ValueError as e:
        raise Unsupported(f"a float fact {v!r}") from e
    if v.lower() in ("nan", "inf", "-inf", "infinity", "-infinity"):
        raise Unsupported("non-finite float facts")
    return v if re.search(r"[.eE]", v) else v + ".0"


def git_show(repo, commit, path):
    r = subprocess.run(["git", "-C", repo, "show", f"{commit}:{path}"], capture_output=True)
    return r.stdout.decode("utf-8", "replace") if r.returncode == 0 else None


def translate(repo, commit, suite, name, files):
    base = f"tests/{suite}/{name}"
    src = git_show(repo, commit, f"{base}/{name}.dl")
    if src is None:
        raise Unsupported("no program file")
    if re.search(r"^\s*#", src, re.M):
        raise Unsupported("the C preprocessor")
    if re.search(r"\b\d+\.\d+\.\d+\.\d+\b", src):
        raise Unsupported("IPv4 literals")
    err = git_show(repo, commit, f"{base}/{name}.err") or ""
    p = Program()
    stmts = statements(tokens(src))
    for s in stmts:
        if s[0][0] == "directive":
            read_directive(p, s)
        else:
            p.clauses.append(s)
    # A missing fact file is reported ("Error loading ...") but the program still runs.
    rejected = any("Error" in l and not l.startswith("Error loading") for l in err.splitlines())
    if rejected:
        for pattern, why in OUTSIDE_THE_LANGUAGE:
            if re.search(pattern, err):
                raise Unsupported(why)
    lines = [f"// Soufflé {suite}/{name} ({commit[:9]}), translated by engine/tests/souffle/import.py"]
    types = {}
    for rel, cols in p.decls.items():
        tys = [p.base(t) for _, t in cols]
        types[rel] = tys
        names = [c if c[0].isalpha() else "c" + c for c, _ in cols]
        line = ".decl s_%s(%s)" % (rel, ", ".join(f"{c}: {t}" for c, t in zip(names, tys)))
        lines.extend([line] * (1 + p.duplicates.count(rel)))
    for rel, ps in p.inputs.items():
        if rel not in types:
            raise Unsupported("an .input of an undeclared relation")
        if ps.get("IO", "file") != "file":
            raise Unsupported(f"input IO={ps.get('IO')}")
        if set(ps) - {"IO", "filename", "delimiter", "headers"}:
            raise Unsupported("fact file formats (" + ", ".join(sorted(set(ps) - {"IO", "filename", "delimiter", "headers"})) + ")")
        fname = ps.get("filename", f"{rel}.facts")
        delim = ps.get("delimiter", "\t").encode().decode("unicode_escape")
        facts = git_show(repo, commit, f"{base}/facts/{fname}")
        if facts is None:
            facts = git_show(repo, commit, f"{base}/{fname}")
        if facts is None:
            # Soufflé reports the missing file and goes on with the relation empty.
            continue
        flines = facts.splitlines()
        if ps.get("headers") == "true":
            flines = flines[1:]
        for line in flines:
            if not line.strip() and len(types[rel]) > 0:
                continue
            vals = line.split(delim) if types[rel] else []
            if len(vals) != len(types[rel]):
                raise Unsupported("a facts line of the wrong arity")
            lines.append("s_%s(%s)." % (rel, ", ".join(fact_value(v, t) for v, t in zip(vals, types[rel]))))
    for c in p.clauses:
        lines.extend(translate_clause(p, c))
    expected = {}
    if not rejected:
        for rel, ps in p.outputs.items():
            if ps.get("IO", "file") != "file":
                raise Unsupported(f"output IO={ps.get('IO')}")
            if rel not in types:
                raise Unsupported("an .output of an undeclared relation")
            if set(ps) - {"IO", "filename", "delimiter", "headers"}:
                raise Unsupported("output file formats")
            fname = ps.get("filename", f"{rel}.csv")
            csv = git_show(repo, commit, f"{base}/{fname}")
            if csv is None:
                raise Unsupported(f"no expected output {fname}")
            olines = csv.splitlines()
            if ps.get("headers") == "true":
                olines = olines[1:]
            delim = ps.get("delimiter", "\t").encode().decode("unicode_escape")
            if delim != "\t":
                olines = ["\t".join(l.split(delim)) for l in olines]
            expected[rel] = "".join(l + "\n" for l in olines)
        out = git_show(repo, commit, f"{base}/{name}.out") or ""
        for rel in p.printsizes:
            if rel not in types:
                raise Unsupported("a .printsize of an undeclared relation")
            sizes = [l.split("\t")[1] for l in out.splitlines() if l.startswith(rel + "\t")]
            if len(sizes) != 1:
                raise Unsupported(f"no printed size of {rel}")
            expected[rel + ".size"] = sizes[0].strip() + "\n"
        if not expected:
            raise Unsupported("no output to compare")
    program = "\n".join(lines) + "\n"
    if len(program) > MAX_PROGRAM_BYTES:
        raise Unsupported(f"too large to keep ({len(program)} bytes)")
    return program, expected, rejected


def main():
    repo = sys.argv[1]
    commit = sys.argv[2] if len(sys.argv) > 2 else "HEAD"
    commit = subprocess.run(["git", "-C", repo, "rev-parse", commit], capture_output=True,
                            text=True, check=True).stdout.strip()
    here = os.path.dirname(os.path.abspath(__file__))
    cases = os.path.join(here, "cases")
    listing = subprocess.run(["git", "-C", repo, "ls-tree", "-r", "--name-only", commit, "tests"],
                             capture_output=True, text=True, check=True).stdout.split("\n")
    tests = {}
    for path in listing:
        parts = path.split("/")
        if len(parts) >= 4 and parts[1] in SUITES:
            tests.setdefault((parts[1], parts[2]), []).append("/".join(parts[3:]))
    excluded = []
    kept = 0
    for (suite, name), files in sorted(tests.items()):
        try:
            program, expected, rejected = translate(repo, commit, suite, name, files)
        except Unsupported as e:
            excluded.append((suite, name, str(e)))
            continue
        d = os.path.join(cases, suite, name)
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, "program.dl"), "w") as f:
            f.write(program)
        if rejected:
            with open(os.path.join(d, "rejected"), "w") as f:
                f.write("Soufflé refuses this program.\n")
        for rel, csv in expected.items():
            # `REL.size`: the size `.printsize REL` prints; `REL.csv`: the relation.
            fname = rel if rel.endswith(".size") else f"{rel}.csv"
            with open(os.path.join(d, fname), "w") as f:
                f.write(csv)
        kept += 1
    with open(os.path.join(here, "excluded.tsv"), "w") as f:
        f.write("suite\ttest\tfeature Scenalog lacks\n")
        for row in excluded:
            f.write("\t".join(row) + "\n")
    with open(os.path.join(here, "SOURCE"), "w") as f:
        f.write(f"https://github.com/souffle-lang/souffle {commit}\n")
    print(f"{kept} cases, {len(excluded)} excluded")


if __name__ == "__main__":
    main()
