//! The translation proper: a RefAV program's Python AST, statement by statement, into Scenalog
//! clauses.
//!
//! Every RefAV value of scenario type (a dict of track → timestamps, possibly with related
//! objects) becomes a helper relation `name(X, T)` holding its (track, frame) pairs, plus, when it
//! can have related objects, `name_r(X, Y, T)`. Each assignment gives one such relation named
//! after the Python variable; nested calls give intermediate helpers named after the function.

use std::collections::{BTreeMap, BTreeSet};

/// The distance of the prelude's `at_a_crosswalk` (`rules/prelude.dl`): RefAV's
/// `at_pedestrian_crossing` at this distance means the same and is written with it; a test
/// checks the prelude still says so.
pub(crate) const AT_A_CROSSWALK_M: f64 = 1.0;

use rustpython_parser::ast::{self, Constant, Expr, Ranged, Stmt};

use scenalog_facts::catalog;

use crate::signatures::{self, Default, Kind, Signature};
use crate::{Defect, ImportError, Imported, Semantics};

mod args;
mod combine;
mod filters;
mod python;
mod relational;

/// A scenario value: the relation holding its (track, frame) pairs and, if it can have related
/// objects, the relation holding (track, related, frame).
#[derive(Debug, Clone)]
pub(crate) struct Scen {
    rel: String,
    rel_r: Option<String>,
    /// The category of the `get_objects_of_category` call whose key order the scenario's keys
    /// follow (RefAV iterates over candidates in that order), when one call's is.
    keys: Option<String>,
}

/// A Python value the importer can follow.
#[derive(Debug, Clone)]
pub(crate) enum Val {
    Scen(Scen),
    LogDir,
    OutputDir,
    Str(String),
    Num(f64),
    Bool(bool),
    None,
    List(Vec<Val>),
    /// A RefAV function named as a value (the argument of a wrapper).
    Func(&'static Signature),
    /// `scenario_not(f)` or `reverse_relationship(f)`.
    Wrapped(&'static str, &'static Signature),
    /// `scenario_not(reverse_relationship(f))`.
    NotReversed(&'static Signature),
    /// The value of an assignment that failed to translate (already reported).
    Poison,
}

impl Val {
    fn kind_name(&self) -> &'static str {
        match self {
            Val::Scen(_) => "a scenario",
            Val::LogDir => "log_dir",
            Val::OutputDir => "output_dir",
            Val::Str(_) => "a string",
            Val::Num(_) => "a number",
            Val::Bool(_) => "a boolean",
            Val::None => "None",
            Val::List(_) => "a list",
            Val::Func(_) => "a function",
            Val::Wrapped(..) | Val::NotReversed(_) => "a wrapped function",
            Val::Poison => "an untranslated value",
        }
    }
}

/// The largest `forward_thresh` / `lateral_thresh` the catalog's `crossing_detail` covers.
pub(crate) const CROSSING_MAX_REACH: f64 = 30.0;
pub(crate) const CROSSING_MAX_OFF: f64 = 15.0;

/// Names the catalog and the output use, which helpers must not take.
pub(crate) const RESERVED: &[&str] = &["referred", "related"];

pub(crate) struct Translator<'a> {
    source: &'a str,
    line_starts: Vec<usize>,
    vars: BTreeMap<String, Val>,
    used_names: BTreeSet<String>,
    clauses: Vec<String>,
    notes: Vec<String>,
    outputs: Vec<(usize, Scen, Option<String>)>,
    errors: Vec<ImportError>,
    /// The line of the statement being translated.
    line: usize,
    /// The program uses RefAV's first API (`accelerating(..., thresh=...)`).
    first_api: bool,
    /// The definitions targeted.
    semantics: Semantics,
    /// The name of the crosswalk loop's frame helpers, once emitted
    /// ([`Translator::crosswalk_frames`]).
    crosswalk_frames: Option<String>,
    /// Per scenario relation, the relation of its objects whatever the frame, once emitted
    /// ([`Translator::keys_of`]).
    keys: BTreeMap<String, String>,
}

pub(crate) type Res<T> = Result<T, ImportError>;

impl Translator<'_> {
    /// The program targets RefAV's definitions.
    pub(crate) fn refav(&self) -> bool {
        matches!(self.semantics, Semantics::Refav(_))
    }
}

/// The construct of the error raised by a use of [`Val::Poison`], never reported.
pub(crate) const POISON: &str = "\0poison";

/// Translates one RefAV program; see [`crate::translate`].
pub fn translate(
    source: &str,
    path: &str,
    semantics: Semantics,
) -> Result<Imported, Vec<ImportError>> {
    let mut t = Translator {
        source,
        line_starts: std::iter::once(0)
            .chain(source.match_indices('\n').map(|(i, _)| i + 1))
            .collect(),
        vars: BTreeMap::new(),
        used_names: BTreeSet::new(),
        clauses: Vec::new(),
        notes: Vec::new(),
        outputs: Vec::new(),
        errors: Vec::new(),
        line: 0,
        first_api: false,
        semantics,
        crosswalk_frames: None,
        keys: BTreeMap::new(),
    };
    // Parsing, translating and dropping the tree each recurse once per level: a program nesting
    // past the limits is an error for its file, before any of them starts.
    if let Some(deep) = crate::nesting::too_deep(source) {
        return Err(vec![ImportError {
            line: t.line_of(deep.offset),
            construct: "nesting".into(),
            message: format!("too deep to translate: {}", deep.what),
            refav_broken: false,
        }]);
    }
    use rustpython_parser::Parse;
    let suite = match ast::Suite::parse(source, path) {
        Ok(s) => s,
        Err(e) => {
            let line = t.line_of(usize::from(e.offset));
            return Err(vec![ImportError {
                line,
                construct: "Python syntax".into(),
                message: format!("not valid Python: {}", e.error),
                refav_broken: true,
            }]);
        }
    };
    // RefAV runs a program with `description` (the file's description), `log_dir`,
    // `output_dir` and `is_gt` defined.
    let stem = path
        .rsplit(['/', '\\'])
        .next()
        .unwrap_or(path)
        .trim_end_matches(".txt")
        .trim_end_matches(".py");
    t.vars
        .insert("description".into(), Val::Str(stem.to_string()));
    t.vars.insert("is_gt".into(), Val::Bool(false));
    for stmt in &suite {
        t.line = t.line_of(usize::from(stmt.range().start()));
        if let Err(e) = t.stmt(stmt) {
            if e.construct == POISON {
                continue; // a use of a value whose error is already reported
            }
            let stop = e.refav_broken;
            t.errors.push(e);
            if stop {
                break; // Python stops at the first exception
            }
        }
    }
    if !t.errors.is_empty() {
        return Err(t.errors);
    }
    let Some((out_line, scen, desc)) = t.outputs.last().cloned() else {
        return Err(vec![ImportError {
            line: t.line_starts.len(),
            construct: "output_scenario".into(),
            message: "the program never calls output_scenario(...), so it has no result".into(),
            refav_broken: true,
        }]);
    };
    if t.outputs.len() > 1 {
        t.notes.push(format!(
            "output_scenario is called {} times; the last call (line {out_line}) is the result, as \
             each call overwrites RefAV's output for the description",
            t.outputs.len()
        ));
    }
    let description = desc.or_else(|| match t.vars.get("description") {
        Some(Val::Str(s)) => Some(s.clone()),
        _ => None,
    });
    let mut text = String::new();
    if let Some(d) = &description {
        text.push_str(&format!("// description: {}\n", one_line(d)));
    }
    text.push_str(&format!(
        "// Imported from the RefAV program {} by `scenalog import refav`.\n",
        one_line(path)
    ));
    text.push_str(if t.first_api {
        "// RefAV API: first (accelerating(..., thresh=...), before CainanD/RefAV 5c5be64)\n"
    } else {
        "// RefAV API: current (CainanD/RefAV 5c5be64)\n"
    });
    text.push_str(&match t.semantics {
        Semantics::Scenalog => "// Semantics: scenalog (Scenalog's definitions)\n".to_string(),
        Semantics::Refav(defects) => format!(
            "// Semantics: refav (RefAV's definitions where the catalog has them: refav_*)\n\
             // RefAV defects reproduced: {defects}\n"
        ),
    });
    for n in &t.notes {
        text.push_str(&format!("// note: {}\n", one_line(n)));
    }
    text.push('\n');
    for c in &t.clauses {
        text.push_str(c);
        text.push('\n');
    }
    text.push_str(&format!("\n// line {out_line}: output_scenario\n"));
    text.push_str(&format!("referred(X, T) :- {}(X, T).\n", scen.rel));
    if let Some(r) = &scen.rel_r {
        text.push_str(&format!("related(X, Y, T) :- {r}(X, Y, T).\n"));
    }
    Ok(Imported {
        description,
        program: text,
        notes: t.notes,
        first_api: t.first_api,
    })
}

pub(crate) fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

pub(crate) fn fmt_num(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{x:.1}")
    } else {
        format!("{x}")
    }
}

impl Translator<'_> {
    pub(crate) fn line_of(&self, offset: usize) -> usize {
        match self.line_starts.binary_search(&offset) {
            Ok(i) => i + 1,
            Err(i) => i,
        }
    }

    pub(crate) fn err(&self, construct: &str, message: String) -> ImportError {
        ImportError {
            line: self.line,
            construct: construct.into(),
            message,
            refav_broken: false,
        }
    }

    /// An error RefAV itself raises on this program (Python's `TypeError`, `NameError`, …).
    pub(crate) fn broken(&self, construct: &str, message: String) -> ImportError {
        ImportError {
            line: self.line,
            construct: construct.into(),
            message: format!("{message} (RefAV raises on this too)"),
            refav_broken: true,
        }
    }

    pub(crate) fn src(&self, e: &impl Ranged) -> String {
        let r = e.range();
        self.source
            .get(usize::from(r.start())..usize::from(r.end()))
            .unwrap_or("")
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
    }

    pub(crate) fn fresh(&mut self, hint: &str) -> String {
        let mut base: String = hint
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() {
                    c.to_ascii_lowercase()
                } else {
                    '_'
                }
            })
            .collect();
        if base.is_empty() || !base.starts_with(|c: char| c.is_ascii_lowercase()) {
            base = format!("v_{base}");
        }
        let taken = |n: &str, used: &BTreeSet<String>| {
            used.contains(n)
                || RESERVED.contains(&n)
                || scenalog_facts::catalog::relation(n).is_some()
                || used.contains(&format!("{n}_r"))
        };
        let mut name = base.clone();
        let mut k = 2;
        while taken(&name, &self.used_names) || taken(&format!("{name}_r"), &self.used_names) {
            name = format!("{base}_{k}");
            k += 1;
        }
        self.used_names.insert(name.clone());
        self.used_names.insert(format!("{name}_r"));
        name
    }

    /// The relation `K(X)` holding `scen`'s objects whatever the frame (the keys of RefAV's
    /// scenario dict), emitted once per scenario. Joined instead of `scen(X, _)`, so that each
    /// object is one tuple, not one per frame.
    pub(crate) fn keys_of(&mut self, scen: &Scen) -> String {
        if let Some(k) = self.keys.get(&scen.rel) {
            return k.clone();
        }
        let k = self.fresh(&format!("{}_keys", scen.rel));
        self.emit(format!("{k}(X) :- {}(X, _).", scen.rel));
        self.keys.insert(scen.rel.clone(), k.clone());
        k
    }

    pub(crate) fn emit(&mut self, clause: String) {
        self.clauses.push(clause);
    }

    pub(crate) fn apply(
        &mut self,
        sig: &'static Signature,
        args: BTreeMap<&'static str, Val>,
        hint: Option<&str>,
    ) -> Res<Val> {
        self.log_dir(sig.name, &args)?;
        let f = sig.name;
        let a = |k: &str| args.get(k).cloned().unwrap_or(Val::None);
        match sig.kind {
            Kind::Source => {
                let cat = self.category(f, &a("category"))?;
                let out = self.fresh(hint.unwrap_or("objects"));
                self.emit(format!(
                    "{out}(X, T) :- category(X, \"{cat}\"), present(X, T)."
                ));
                Ok(Val::Scen(Scen {
                    rel: out,
                    rel_r: None,
                    keys: Some(cat),
                }))
            }
            Kind::Filter => {
                let input = self.scen(f, sig.params[0].0, &a(sig.params[0].0))?;
                let body = self.filter_body(f, &args)?;
                Ok(Val::Scen(self.filter(&input, &body, hint.unwrap_or(f))))
            }
            Kind::Relational => {
                if f == "get_objects_in_relative_direction" {
                    let (sel, _) = self.relational(sig, &args, "objects_in_direction", false)?;
                    let tracks = self.scen(f, sig.params[0].0, &a(sig.params[0].0))?;
                    let cands = self.scen(f, sig.params[1].0, &a(sig.params[1].0))?;
                    let keys = self.relation_keys(sig, &args, &tracks)?;
                    let reversed =
                        self.reverse(&sel, (&tracks, &cands), keys.as_deref(), hint.unwrap_or(f));
                    return Ok(Val::Scen(reversed));
                }
                let (_, scen) = self.relational(sig, &args, hint.unwrap_or(f), true)?;
                Ok(Val::Scen(scen))
            }
            Kind::Combine => {
                let Val::List(items) = a("scenario_dicts") else {
                    return Err(self.broken(
                        f,
                        format!(
                            "{f}() takes a list of scenarios, got {}",
                            a("scenario_dicts").kind_name()
                        ),
                    ));
                };
                let mut scens = Vec::new();
                for (i, v) in items.iter().enumerate() {
                    scens.push(self.scen(f, &format!("scenario_dicts[{i}]"), v)?);
                }
                if scens.is_empty() {
                    return Err(self.broken(f, format!("{f}([]) has nothing to combine")));
                }
                Ok(Val::Scen(self.combine(
                    f == "scenario_and",
                    &scens,
                    hint.unwrap_or(f),
                )))
            }
            Kind::Wrapper => match a("func") {
                Val::Func(inner) => {
                    if f == "reverse_relationship" && inner.kind != Kind::Relational {
                        return Err(self.broken(
                            f,
                            format!(
                                "TypeError: reverse_relationship({})(...) calls {}() with (track_candidates, related_candidates, log_dir), which it does not take",
                                inner.name, inner.name
                            ),
                        ));
                    }
                    if f == "scenario_not" && !matches!(inner.kind, Kind::Filter | Kind::Relational)
                    {
                        return Err(self.broken(
                            f,
                            format!(
                                "scenario_not({}) needs a function that takes log_dir",
                                inner.name
                            ),
                        ));
                    }
                    Ok(Val::Wrapped(sig.name, inner))
                }
                Val::Wrapped("reverse_relationship", inner) if f == "scenario_not" => {
                    Ok(Val::NotReversed(inner))
                }
                other => Err(self.broken(
                    f,
                    format!(
                        "ValueError: {f}() wraps a RefAV function that takes log_dir, got {}",
                        other.kind_name()
                    ),
                )),
            },
            Kind::Output => {
                let scen = self.scen(f, "scenario", &a("scenario"))?;
                let desc = match a("description") {
                    Val::Str(s) => Some(s),
                    _ => None,
                };
                self.outputs.push((self.line, scen, desc));
                Ok(Val::None)
            }
        }
    }
}
