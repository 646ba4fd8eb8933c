//! The prelude: the concepts descriptions use ("stopped", "near", "at an intersection", "a group",
//! …) as derived relations written once in Scenalog (`rules/prelude.dl`), available to every
//! program without being pasted in.
//!
//! The checker adds to a program the clauses of the prelude relations it uses but does not define
//! (and of the prelude relations those use), so the engine evaluates them and proofs descend into
//! them like any other rule. A program that defines a relation of a prelude name uses its own
//! definition; one that defines a name a prelude relation it uses depends on is an error
//! ([`crate::diagnostics::SHADOWED_PRELUDE`]), since the prelude relation would silently change
//! meaning. The catalog listing, the synthesis prompt's conventions and the docs are rendered from
//! [`relations`].

use std::collections::{BTreeMap, BTreeSet};
use std::sync::OnceLock;

use scenalog_facts::catalog::{self, ColType};

use crate::ast::{Aggregate, Atom, Clause, Decl, Expr, ExprKind, Literal, Program, Span};
use crate::diagnostics::{self, error};
use crate::walk::body_atoms;
use crate::Diagnostic;

/// The prelude's source text.
pub const SOURCE: &str = include_str!("../prelude.dl");

/// Where the prelude lives in the repository, for messages that point at one of its rules.
pub const PATH: &str = "rules/prelude.dl";

/// The 1-based line in [`PATH`] and the text of a clause the checker added to a program whose
/// own text is `program_len` bytes long; `None` for the program's own clauses.
pub fn clause_text(program_len: usize, span: Span) -> Option<(usize, String)> {
    let at = program_len + 1;
    if span.start < at {
        return None;
    }
    let (a, b) = (span.start - at, span.end - at);
    let text = SOURCE.get(a..b)?.trim().to_string();
    let line = SOURCE.get(..a)?.matches('\n').count() + 1;
    Some((line, text))
}

/// One relation of the prelude.
#[derive(Debug, Clone, PartialEq)]
pub struct PreludeRelation {
    /// Its name.
    pub name: String,
    /// Column names and types, from its `.decl`.
    pub columns: Vec<(String, ColType)>,
    /// The one-line doc written above its `.decl`.
    pub doc: String,
    /// Its clauses as written in the prelude, one per line (continuation lines joined).
    pub definition: Vec<String>,
    /// The other prelude relations its clauses use.
    pub uses: Vec<String>,
}

impl PreludeRelation {
    /// `name(Col: type, …)`.
    pub fn signature(&self) -> String {
        let cols: Vec<String> = self
            .columns
            .iter()
            .map(|(n, t)| format!("{n}: {}", t.as_str()))
            .collect();
        format!("{}({})", self.name, cols.join(", "))
    }

    /// As JSON: name, columns (name and type), doc, definition (one clause a string), its group
    /// (`"Concepts (prelude)"`) and `"prelude": true`.
    pub fn to_json(&self) -> serde_json::Value {
        let columns: Vec<serde_json::Value> = self
            .columns
            .iter()
            .map(|(n, t)| serde_json::json!({ "name": n, "type": t.as_str() }))
            .collect();
        serde_json::json!({
            "name": self.name,
            "columns": columns,
            "doc": self.doc,
            "definition": self.definition,
            "group": "Concepts (prelude)",
            "prelude": true,
        })
    }

    /// Its arity.
    pub fn arity(&self) -> usize {
        self.columns.len()
    }
}

struct Parsed {
    program: Program,
    relations: Vec<PreludeRelation>,
}

fn parsed() -> &'static Parsed {
    static PARSED: OnceLock<Parsed> = OnceLock::new();
    PARSED.get_or_init(|| {
        let (program, _) = crate::parser::parse(SOURCE);
        let names: BTreeSet<&str> = program.decls.iter().map(|d| d.name.as_str()).collect();
        let relations = program
            .decls
            .iter()
            .map(|d| {
                let clauses: Vec<&Clause> = program
                    .clauses
                    .iter()
                    .filter(|c| c.head.pred == d.name)
                    .collect();
                let mut uses = BTreeSet::new();
                for c in &clauses {
                    for (a, _) in body_atoms(&c.body) {
                        if a.pred != d.name && names.contains(a.pred.as_str()) {
                            uses.insert(a.pred.clone());
                        }
                    }
                }
                PreludeRelation {
                    name: d.name.clone(),
                    columns: d.columns.clone(),
                    doc: doc_above(d.span.start),
                    definition: clauses
                        .iter()
                        .map(|c| one_line(&SOURCE[c.span.start..c.span.end]))
                        .collect(),
                    uses: uses.into_iter().collect(),
                }
            })
            .collect();
        Parsed { program, relations }
    })
}

/// The `///` lines directly above byte `start` of the prelude, joined.
fn doc_above(start: usize) -> String {
    let before = &SOURCE[..start];
    let mut lines: Vec<&str> = before
        .lines()
        .rev()
        .skip_while(|l| l.trim().is_empty())
        .take_while(|l| l.trim_start().starts_with("///"))
        .map(|l| l.trim_start().trim_start_matches("///").trim())
        .collect();
    lines.reverse();
    lines.join(" ")
}

fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Every prelude relation, in the prelude's order.
pub fn relations() -> &'static [PreludeRelation] {
    &parsed().relations
}

/// The prelude relation of this name, if there is one.
pub fn relation(name: &str) -> Option<&'static PreludeRelation> {
    relations().iter().find(|r| r.name == name)
}

/// The prelude as the catalog listing and the synthesis prompt show it: per relation, its
/// signature and doc, then its definition indented.
pub fn render_text() -> String {
    let mut out = String::new();
    for r in relations() {
        if is_helper(r) {
            continue;
        }
        out.push_str(&format!("{}: {}\n", r.signature(), r.doc));
        let helpers = r
            .uses
            .iter()
            .filter_map(|u| relation(u))
            .filter(|h| is_helper(h));
        for line in r
            .definition
            .iter()
            .chain(helpers.flat_map(|h| &h.definition))
        {
            out.push_str(&format!("    {line}\n"));
        }
    }
    out
}

/// Whether a relation is only a step of another's definition (its doc does not stand alone):
/// the listing shows it inside the definitions that use it.
pub fn is_helper(r: &PreludeRelation) -> bool {
    relations()
        .iter()
        .any(|o| o.name != r.name && o.uses.contains(&r.name))
        && HELPERS.contains(&r.name.as_str())
}

/// Prelude relations that exist to define others.
const HELPERS: &[&str] = &["lead_blocked", "wrong_way_for_2s", "group_link"];

/// The prelude relations a program needs: those its clauses use but do not define, and the
/// prelude relations they use in turn, in the prelude's order.
fn needed(program: &Program) -> (Vec<&'static PreludeRelation>, BTreeMap<String, String>) {
    let defined: BTreeSet<&str> = program
        .clauses
        .iter()
        .map(|c| c.head.pred.as_str())
        .chain(program.decls.iter().map(|d| d.name.as_str()))
        .collect();
    let mut want: BTreeSet<String> = BTreeSet::new();
    let mut stack: Vec<String> = Vec::new();
    for c in &program.clauses {
        for (a, _) in body_atoms(&c.body) {
            let p = a.pred.as_str();
            if !defined.contains(p) && catalog::relation(p).is_none() && relation(p).is_some() {
                stack.push(p.to_string());
            }
        }
    }
    // Names a needed prelude relation uses but the program defines: by whom.
    let mut shadowed: BTreeMap<String, String> = BTreeMap::new();
    while let Some(name) = stack.pop() {
        if !want.insert(name.clone()) {
            continue;
        }
        if let Some(r) = relation(&name) {
            for u in &r.uses {
                if defined.contains(u.as_str()) {
                    shadowed.entry(u.clone()).or_insert_with(|| name.clone());
                } else {
                    stack.push(u.clone());
                }
            }
        }
    }
    let chosen = relations()
        .iter()
        .filter(|r| want.contains(&r.name))
        .collect();
    (chosen, shadowed)
}

/// The program's own definitions of prelude concepts: a warning ([`diagnostics::REDEFINED_PRELUDE`])
/// for each relation the program defines under a prelude name with the prelude's arity (its
/// definition replaces the prelude's, which the warning quotes), an error
/// ([`diagnostics::PRELUDE_ARITY`]) where the arity differs. Names a used prelude relation
/// depends on are [`extend`]'s error instead.
pub fn redefinitions(program: &Program) -> Vec<Diagnostic> {
    let (_, shadowed) = needed(program);
    let mut seen: BTreeSet<&str> = BTreeSet::new();
    let mut out = Vec::new();
    let heads = program
        .clauses
        .iter()
        .map(|c| (c.head.pred.as_str(), c.head.pred_span, c.head.args.len()));
    let decls = program
        .decls
        .iter()
        .map(|d| (d.name.as_str(), d.name_span, d.columns.len()));
    for (name, span, arity) in decls.chain(heads) {
        let Some(r) = relation(name) else { continue };
        if shadowed.contains_key(name) || !seen.insert(name) {
            continue;
        }
        let line = parsed()
            .program
            .clauses
            .iter()
            .find(|c| c.head.pred == name)
            .map_or(0, |c| SOURCE[..c.span.start].matches('\n').count() + 1);
        let prelude = format!(
            "{} ({PATH}:{line}: `{}`)",
            r.signature(),
            r.definition.first().map_or("", String::as_str)
        );
        let d = if arity != r.columns.len() {
            error(
                diagnostics::PRELUDE_ARITY,
                span,
                format!(
                    "`{name}` is a prelude concept with {} columns, {prelude}; this program defines a `{name}` of {arity}",
                    r.columns.len()
                ),
            )
            .with_hint(format!(
                "name your relation differently (e.g. `my_{name}`), or use the prelude's `{}`",
                r.signature()
            ))
        } else {
            diagnostics::warning(
                diagnostics::REDEFINED_PRELUDE,
                span,
                format!(
                    "`{name}` is a prelude concept, {prelude}; this program's definition replaces it"
                ),
            )
            .with_hint(format!(
                "to mean the prelude's `{name}`, delete these clauses and use it; for a variant, \
                 give it its own name (e.g. `{name}_here`)"
            ))
        };
        out.push(d);
    }
    out
}

/// Adds to `program` the declarations and clauses of the prelude relations it needs, their spans
/// moved to start at `offset` (past the program's own text, so a span tells whose text it is),
/// and returns their names with an error for each program relation that shadows a name a needed
/// prelude relation uses.
pub fn extend(program: &mut Program, offset: usize) -> (Vec<String>, Vec<Diagnostic>) {
    let (chosen, shadowed) = needed(program);
    let mut diags = Vec::new();
    for (name, user) in &shadowed {
        let span = program
            .clauses
            .iter()
            .find(|c| &c.head.pred == name)
            .map(|c| c.head.pred_span)
            .or_else(|| {
                program
                    .decls
                    .iter()
                    .find(|d| &d.name == name)
                    .map(|d| d.name_span)
            })
            .unwrap_or_default();
        diags.push(
            error(
                diagnostics::SHADOWED_PRELUDE,
                span,
                format!(
                    "`{name}` is a prelude relation that the prelude's `{user}` uses: defining it here would change what `{user}` means"
                ),
            )
            .with_hint(format!(
                "give your relation another name (e.g. `my_{name}`), or define `{user}` yourself too"
            )),
        );
    }
    if chosen.is_empty() || !diags.is_empty() {
        return (Vec::new(), diags);
    }
    let names: BTreeSet<&str> = chosen.iter().map(|r| r.name.as_str()).collect();
    let source = &parsed().program;
    for d in &source.decls {
        if names.contains(d.name.as_str()) {
            let mut d: Decl = d.clone();
            d.name_span = shift(d.name_span, offset);
            d.span = shift(d.span, offset);
            program.decls.push(d);
        }
    }
    for c in &source.clauses {
        if names.contains(c.head.pred.as_str()) {
            let mut c = c.clone();
            shift_clause(&mut c, offset);
            program.clauses.push(c);
        }
    }
    (chosen.iter().map(|r| r.name.clone()).collect(), diags)
}

/// Where a program writes out a prelude relation's definition instead of using it: `(clause
/// index, relation)` for every clause of `program` whose body contains every literal of a
/// clause of a prelude relation (at least two literals, variables renamed, `<` and `<=` alike,
/// `>` and `>=` alike, constants equal). A variant with another threshold is not one.
pub fn rederivations(program: &Program) -> Vec<(usize, &'static str)> {
    let source = &parsed().program;
    let mut out = Vec::new();
    for (i, c) in program.clauses.iter().enumerate() {
        for pc in &source.clauses {
            if pc.body.len() < 2 {
                continue;
            }
            let mut map = BTreeMap::new();
            if embeds(&pc.body, &c.body, &mut map) {
                if let Some(r) = relation(&pc.head.pred) {
                    if !out.contains(&(i, r.name.as_str())) {
                        out.push((i, r.name.as_str()));
                    }
                }
            }
        }
    }
    out
}

/// Whether every literal of `pattern` matches some literal of `body` under one renaming.
fn embeds(pattern: &[Literal], body: &[Literal], map: &mut BTreeMap<String, String>) -> bool {
    let Some((first, rest)) = pattern.split_first() else {
        return true;
    };
    body.iter().any(|l| {
        let mut m = map.clone();
        if literal_matches(first, l, &mut m) && embeds(rest, body, &mut m) {
            *map = m;
            true
        } else {
            false
        }
    })
}

fn literal_matches(p: &Literal, l: &Literal, map: &mut BTreeMap<String, String>) -> bool {
    use crate::ast::CmpOp::{Ge, Gt, Le, Lt};
    match (p, l) {
        (Literal::Pos(a), Literal::Pos(b)) | (Literal::Neg(a, _), Literal::Neg(b, _)) => {
            a.pred == b.pred
                && a.args.len() == b.args.len()
                && a.args
                    .iter()
                    .zip(&b.args)
                    .all(|(x, y)| expr_matches(x, y, map))
        }
        (Literal::Cmp(x), Literal::Cmp(y)) => {
            let class = |op| match op {
                Lt | Le => 0,
                Gt | Ge => 1,
                other => 2 + other as u8,
            };
            class(x.op) == class(y.op)
                && expr_matches(&x.lhs, &y.lhs, map)
                && expr_matches(&x.rhs, &y.rhs, map)
        }
        _ => false,
    }
}

fn expr_matches(p: &Expr, e: &Expr, map: &mut BTreeMap<String, String>) -> bool {
    let text = crate::printer::print_expr(e);
    match &p.kind {
        ExprKind::Wildcard => true,
        ExprKind::Var(v) => match map.get(v) {
            Some(t) => *t == text,
            None => {
                map.insert(v.clone(), text);
                true
            }
        },
        ExprKind::Binary(op, x, y) => match &e.kind {
            ExprKind::Binary(op2, x2, y2) => {
                op == op2 && expr_matches(x, x2, map) && expr_matches(y, y2, map)
            }
            _ => false,
        },
        _ => crate::printer::print_expr(p) == text,
    }
}

fn shift(s: Span, by: usize) -> Span {
    Span::new(s.start + by, s.end + by)
}

fn shift_clause(c: &mut Clause, by: usize) {
    c.span = shift(c.span, by);
    shift_atom(&mut c.head, by);
    shift_body(&mut c.body, by);
}

fn shift_body(body: &mut [Literal], by: usize) {
    for l in body {
        match l {
            Literal::Pos(a) => shift_atom(a, by),
            Literal::Neg(a, s) => {
                shift_atom(a, by);
                *s = shift(*s, by);
            }
            Literal::Cmp(c) => {
                c.span = shift(c.span, by);
                shift_expr(&mut c.lhs, by);
                shift_expr(&mut c.rhs, by);
            }
            Literal::Agg(g) => shift_aggregate(g, by),
        }
    }
}

fn shift_aggregate(g: &mut Aggregate, by: usize) {
    g.span = shift(g.span, by);
    shift_expr(&mut g.result, by);
    if let Some(t) = &mut g.target {
        shift_expr(t, by);
    }
    shift_body(&mut g.body, by);
}

fn shift_atom(a: &mut Atom, by: usize) {
    a.span = shift(a.span, by);
    a.pred_span = shift(a.pred_span, by);
    for e in &mut a.args {
        shift_expr(e, by);
    }
}

fn shift_expr(e: &mut Expr, by: usize) {
    e.span = shift(e.span, by);
    match &mut e.kind {
        ExprKind::Neg(x) => shift_expr(x, by),
        ExprKind::Binary(_, x, y) => {
            shift_expr(x, by);
            shift_expr(y, by);
        }
        ExprKind::Call(_, xs) => {
            for x in xs {
                shift_expr(x, by);
            }
        }
        ExprKind::Var(_)
        | ExprKind::Wildcard
        | ExprKind::Str(_)
        | ExprKind::Int(_)
        | ExprKind::Float(_)
        | ExprKind::Quantity(_) => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_prelude_parses_and_every_relation_has_a_doc_and_a_definition() {
        let (_, diags) = crate::parser::parse(SOURCE);
        assert!(diags.is_empty(), "{diags:?}");
        assert!(relations().len() >= 20, "{}", relations().len());
        for r in relations() {
            assert!(!r.doc.is_empty(), "{} has no doc", r.name);
            assert!(!r.definition.is_empty(), "{} has no clause", r.name);
            assert!(
                catalog::relation(&r.name).is_none(),
                "{} is a catalog name",
                r.name
            );
        }
        let group = relation("group_size").map(|r| r.uses.clone());
        assert_eq!(group, Some(vec!["in_group".to_string()]));
        let text = render_text();
        assert!(
            text.contains("stopped(X: track, T: time): X is slower than 0.5 m/s"),
            "{text}"
        );
        assert!(!text.contains("lead_blocked(X: track"), "{text}");
        assert!(
            text.contains("lead_blocked(X, Y, T) :- following"),
            "{text}"
        );
    }

    #[test]
    fn the_prelude_checks_clean_on_its_own() {
        // Every relation used by one `referred` rule, so none is an unused helper.
        let uses: Vec<String> = relations()
            .iter()
            .map(|r| {
                let args: Vec<String> = r
                    .columns
                    .iter()
                    .map(|(_, t)| match t {
                        ColType::Track => "X".to_string(),
                        ColType::Time => "T".to_string(),
                        _ => "_".to_string(),
                    })
                    .collect();
                format!("{}({})", r.name, args.join(", "))
            })
            .collect();
        let text = format!(
            "{}\nreferred(X, T) :- present(X, T), {}.\n",
            SOURCE.replace(".decl", "// .decl"),
            uses.join(", ")
        );
        let out = crate::check(&text, &crate::CheckOptions::default());
        let diags: Vec<String> = out
            .diagnostics
            .iter()
            .filter(|d| d.span.start < SOURCE.len())
            // The prelude defines its own concepts, of course.
            .filter(|d| d.code != diagnostics::REDEFINED_PRELUDE)
            .map(|d| {
                format!(
                    "{}: {} at {:?}",
                    d.code,
                    d.message,
                    &text[d.span.start..d.span.end]
                )
            })
            .collect();
        assert!(diags.is_empty(), "{diags:#?}");
    }

    #[test]
    fn a_program_gets_what_it_uses_and_what_that_uses_and_nothing_else() {
        let (mut p, _) =
            crate::parser::parse("referred(P, T) :- group_size(P, T, N), N >= 3, stopped(P, T).");
        let before = p.clauses.len();
        let (names, diags) = extend(&mut p, 100);
        assert!(diags.is_empty());
        assert_eq!(names, ["stopped", "group_link", "in_group", "group_size"]);
        assert_eq!(p.clauses.len(), before + 5);
        assert!(p.clauses[before..].iter().all(|c| c.span.start >= 100));
    }

    #[test]
    fn a_program_that_shadows_what_a_used_prelude_relation_uses_is_an_error() {
        let src = "stopped(X, T) :- speed(X, T, V), V < 2.0.\nreferred(X, T) :- waiting(X, T).";
        let (mut p, _) = crate::parser::parse(src);
        let (names, diags) = extend(&mut p, src.len());
        assert!(names.is_empty());
        assert_eq!(diags.len(), 1, "{diags:?}");
        assert_eq!(diags[0].code, diagnostics::SHADOWED_PRELUDE);
        assert_eq!(&src[diags[0].span.start..diags[0].span.end], "stopped");
        // Its own variant of a relation it uses directly is fine.
        let (mut p, _) = crate::parser::parse(
            "stopped(X, T) :- speed(X, T, V), V < 2.0.\nreferred(X, T) :- stopped(X, T).",
        );
        let (names, diags) = extend(&mut p, 200);
        assert!(names.is_empty() && diags.is_empty());
    }
}
