//! The predicate table: which names are catalog relations, which the program defines or declares,
//! and their arity. Reports unknown predicates, wrong arity, redefined catalog relations, the
//! `referred`/`related` shape by arity, a missing `referred`, and empty or unused helpers.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use scenalog_facts::catalog::{self, ColType};

use crate::ast::{Atom, Program, Span};
use crate::diagnostics::{self, closest, error, warning};
use crate::walk::body_atoms;
use crate::{CheckOptions, Diagnostic, PredKind};

/// The required signature of `referred`.
pub const REFERRED_SIGNATURE: &str = "referred(Track: track, T: time)";
/// The required signature of `related`.
pub const RELATED_SIGNATURE: &str = "related(Track: track, Other: track, T: time)";

/// What the table knows of one predicate.
#[derive(Debug, Clone, PartialEq)]
pub struct PredEntry {
    /// Catalog or derived.
    pub kind: PredKind,
    /// The arity every use must have.
    pub arity: usize,
    /// Where the arity comes from (a `.decl` or the first head), for derived predicates.
    pub origin: Option<Span>,
    /// Whether a clause defines it.
    pub defined: bool,
}

/// The predicate table.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PredTable {
    /// By name: every predicate the program uses, defines or declares (unknown ones left out).
    pub preds: BTreeMap<String, PredEntry>,
}

impl PredTable {
    /// Whether `atom` names a known predicate with the right number of arguments.
    pub fn fits(&self, atom: &Atom) -> bool {
        self.preds
            .get(&atom.pred)
            .is_some_and(|e| e.arity == atom.args.len())
    }
}

/// The required column types of an output predicate (empty for other names).
pub fn output_types(name: &str) -> Vec<ColType> {
    match name {
        "referred" => vec![ColType::Track, ColType::Time],
        "related" => vec![ColType::Track, ColType::Track, ColType::Time],
        _ => Vec::new(),
    }
}

/// The required arity of an output predicate.
pub fn output_arity(name: &str) -> Option<(usize, &'static str)> {
    match name {
        "referred" => Some((2, REFERRED_SIGNATURE)),
        "related" => Some((3, RELATED_SIGNATURE)),
        _ => None,
    }
}

/// Builds the table and reports E0101, E0102, E0402 (arity), E0403, E0404, E0401, W0502, W0503.
pub fn collect(
    program: &Program,
    broken_heads: &[String],
    options: &CheckOptions,
    diags: &mut Vec<Diagnostic>,
) -> PredTable {
    let mut table = PredTable::default();
    // Declarations first: they fix the arity.
    for d in &program.decls {
        if let Some(r) = catalog::relation(&d.name) {
            diags.push(
                error(
                    diagnostics::REDEFINED_CATALOG,
                    d.name_span,
                    format!("`{}` is a catalog relation and cannot be declared", d.name),
                )
                .with_hint(format!(
                    "its signature is {}; give your helper another name",
                    r.signature()
                )),
            );
            continue;
        }
        let mut named = std::collections::HashSet::new();
        if let Some((twice, _)) = d.columns.iter().find(|(c, _)| !named.insert(c.as_str())) {
            diags.push(
                error(
                    diagnostics::DUPLICATE_COLUMN,
                    d.span,
                    format!("`{}` names two columns `{twice}`", d.name),
                )
                .with_hint("give each column its own name"),
            );
        }
        if let Some(prev) = table.preds.get(&d.name) {
            let mut diag = error(
                diagnostics::DUPLICATE_DECL,
                d.name_span,
                format!("`{}` is declared twice", d.name),
            )
            .with_hint("keep one `.decl` line per predicate");
            if let Some(o) = prev.origin {
                diag = diag.with_related(o, "first declared here");
            }
            diags.push(diag);
            continue;
        }
        if let Some((arity, sig)) = output_arity(&d.name) {
            let want = output_types(&d.name);
            let have: Vec<ColType> = d.columns.iter().map(|(_, t)| *t).collect();
            if d.columns.len() != arity || have != want {
                diags.push(
                    error(
                        diagnostics::OUTPUT_SHAPE,
                        d.span,
                        format!(
                            "`{}` must have {arity} columns, this declaration has {}",
                            d.name,
                            d.columns.len()
                        ),
                    )
                    .with_hint(format!("declare it as {sig}")),
                );
                continue;
            }
        }
        table.preds.insert(
            d.name.clone(),
            PredEntry {
                kind: PredKind::Derived,
                arity: d.columns.len(),
                origin: Some(d.span),
                defined: false,
            },
        );
    }
    // Heads: define derived predicates.
    for c in &program.clauses {
        let h = &c.head;
        if let Some(r) = catalog::relation(&h.pred) {
            diags.push(
                error(
                    diagnostics::REDEFINED_CATALOG,
                    h.pred_span,
                    format!("`{}` is a catalog relation: a rule cannot define it", h.pred),
                )
                .with_hint(format!(
                    "catalog relations come from the logs ({}); name your helper differently, e.g. `my_{}`",
                    r.signature(),
                    h.pred
                )),
            );
            continue;
        }
        if let Some((arity, sig)) = output_arity(&h.pred) {
            if h.args.len() != arity {
                diags.push(
                    error(
                        diagnostics::OUTPUT_SHAPE,
                        h.span,
                        format!(
                            "`{}` must have {arity} arguments, found {}",
                            h.pred,
                            h.args.len()
                        ),
                    )
                    .with_hint(format!("the output is {sig}")),
                );
                table.preds.entry(h.pred.clone()).or_insert(PredEntry {
                    kind: PredKind::Derived,
                    arity,
                    origin: None,
                    defined: true,
                });
                continue;
            }
        }
        match table.preds.get_mut(&h.pred) {
            Some(e) => {
                if e.arity != h.args.len() {
                    diags.push(arity_error(h, e.arity, e.origin, None));
                }
                e.defined = true;
            }
            None => {
                table.preds.insert(
                    h.pred.clone(),
                    PredEntry {
                        kind: PredKind::Derived,
                        arity: h.args.len(),
                        origin: Some(h.span),
                        defined: true,
                    },
                );
            }
        }
    }
    // Body atoms.
    let mut used: BTreeSet<&str> = BTreeSet::new();
    let program_names: Vec<String> = table.preds.keys().cloned().collect();
    // The hint of each unknown name, computed once however often the name is used.
    let mut hints: HashMap<String, String> = HashMap::new();
    for c in &program.clauses {
        for (a, _) in body_atoms(&c.body) {
            if a.pred != c.head.pred {
                used.insert(&a.pred);
            }
            if let Some(r) = catalog::relation(&a.pred) {
                if r.arity() != a.args.len() {
                    diags.push(arity_error(a, r.arity(), None, Some(r.signature())));
                }
                table.preds.entry(a.pred.clone()).or_insert(PredEntry {
                    kind: PredKind::Catalog,
                    arity: r.arity(),
                    origin: None,
                    defined: false,
                });
                continue;
            }
            if let Some(e) = table.preds.get(&a.pred) {
                if e.arity != a.args.len() {
                    let sig = output_arity(&a.pred).map(|(_, s)| s.to_string());
                    diags.push(arity_error(a, e.arity, e.origin, sig));
                }
                continue;
            }
            if broken_heads.contains(&a.pred) {
                continue;
            }
            let searched = if hints.len() < HINTED_AMONG_PROGRAM {
                program_names.as_slice()
            } else {
                &[]
            };
            let hint = hints
                .entry(a.pred.clone())
                .or_insert_with(|| unknown_hint(&a.pred, searched));
            diags.push(unknown_predicate(a, hint.clone()));
        }
    }
    // Output.
    let has_referred = program.clauses.iter().any(|c| c.head.pred == "referred");
    if options.require_referred && !has_referred && !broken_heads.iter().any(|b| b == "referred") {
        let span = program
            .clauses
            .first()
            .map_or(Span::new(0, 0), |c| c.head.span);
        diags.push(
            error(
                diagnostics::NO_REFERRED,
                span,
                "the program has no `referred` rule: nothing would be reported",
            )
            .with_hint(format!(
                "add a rule `referred(X, T) :- …` whose head is {REFERRED_SIGNATURE}: the object X the description refers to at T"
            )),
        );
    }
    for d in &program.decls {
        if let Some(e) = table.preds.get(&d.name) {
            if !e.defined && e.origin == Some(d.span) {
                diags.push(
                    warning(
                        diagnostics::EMPTY_PREDICATE,
                        d.name_span,
                        format!(
                            "`{}` is declared but no rule or fact defines it: it is always empty",
                            d.name
                        ),
                    )
                    .with_hint(format!(
                        "add a rule `{}(…) :- …`, or remove the declaration",
                        d.name
                    )),
                );
            }
        }
    }
    if has_referred {
        let mut seen = BTreeSet::new();
        for c in &program.clauses {
            let name = c.head.pred.as_str();
            if output_arity(name).is_some()
                || used.contains(name)
                || catalog::relation(name).is_some()
            {
                continue;
            }
            if seen.insert(name) {
                diags.push(
                    warning(
                        diagnostics::UNUSED_PREDICATE,
                        c.head.pred_span,
                        format!("`{name}` is defined but no other rule uses it"),
                    )
                    .with_hint(format!(
                        "use `{name}` in the body of `referred` or `related`, or remove it"
                    )),
                );
            }
        }
    }
    table
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

fn arity_error(
    a: &Atom,
    want: usize,
    origin: Option<Span>,
    signature: Option<String>,
) -> Diagnostic {
    let mut d = error(
        diagnostics::WRONG_ARITY,
        a.span,
        format!(
            "`{}` takes {want} argument{}, found {}",
            a.pred,
            plural(want),
            a.args.len()
        ),
    );
    if let Some(sig) = signature {
        d = d.with_hint(format!("the signature is {sig}"));
    } else {
        d = d.with_hint(format!(
            "use `{}` with {want} argument{} everywhere",
            a.pred,
            plural(want)
        ));
    }
    if let Some(o) = origin {
        if o != a.span {
            d = d.with_related(
                o,
                format!("`{}` has {want} argument{} here", a.pred, plural(want)),
            );
        }
    }
    d
}

/// How many distinct unknown names are compared with the program's own names for a "did you
/// mean" (every one is compared with the catalog's): past that, a program of thousands of unknown
/// names would cost a comparison of each with each.
const HINTED_AMONG_PROGRAM: usize = 64;

/// The hint of an unknown predicate `name`: the closest catalog relations, prelude relations and
/// `program_names`.
fn unknown_hint(name: &str, program_names: &[String]) -> String {
    let candidates = catalog::catalog()
        .iter()
        .map(|r| r.name)
        .chain(crate::prelude::relations().iter().map(|r| r.name.as_str()))
        .chain(program_names.iter().map(String::as_str));
    let mut seen = std::collections::BTreeSet::new();
    let near: Vec<&str> = closest(name, candidates, 4)
        .into_iter()
        .filter(|n| seen.insert(*n))
        .take(3)
        .collect();
    if near.is_empty() {
        "it is neither a relation of the catalog or the prelude nor defined by a rule here: define it with a rule of its own (`name(X, T) :- …`) or use one of the relations the catalog and the prelude list".to_string()
    } else {
        let names: Vec<String> = near
            .iter()
            .map(
                |n| match (catalog::relation(n), crate::prelude::relation(n)) {
                    (Some(r), _) => format!("`{}`", r.signature()),
                    (None, Some(p)) => format!("`{}` (the prelude's: {})", p.signature(), p.doc),
                    (None, None) => format!("`{n}` (defined in this program)"),
                },
            )
            .collect();
        format!("did you mean {}?", names.join(" or "))
    }
}

fn unknown_predicate(a: &Atom, hint: String) -> Diagnostic {
    error(
        diagnostics::UNKNOWN_PREDICATE,
        a.pred_span,
        format!(
            "unknown predicate `{}`: not in the catalog and not defined by any rule",
            a.pred
        ),
    )
    .with_hint(hint)
}
