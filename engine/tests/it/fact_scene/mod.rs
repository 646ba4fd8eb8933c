//! The fact-scene harness: a scene written as ground facts of catalog relations, served to the
//! engine as its provider, and library programs run on it.
//!
//! A fact scene is written as Datalog ground facts of catalog relations, e.g.
//! `category(1, "BOX_TRUCK"). accel(1, 10, 1.5).`, parsed with the rule language's parser (the
//! AST only: the checker rightly refuses programs that define catalog relations), converted to
//! columns with the catalog's types (a track column takes an integer track id, a time column a
//! frame, a lane column an integer lane id) and served to the engine as the provider. The
//! harness completes the facts as the extractors would: a category fact also gives the
//! super-categories ("VEHICLE" for vehicle categories, "CONSTRUCTION" for road-works objects,
//! "ANY" for every track), an "EGO_VEHICLE"
//! track is `ego`, and the symmetric pair relations `near` and `heading_relative` are given in
//! both orders (a scene states each pair once). It applies every constraint of the engine's
//! requests, as the extractors do, so a constraint the engine derives wrongly loses a staged
//! match and fails here. Every track a fact mentions must have a category, so a scene cannot
//! silently leave one out.
//!
//! Used by `library_facts.rs`; any engine test can `mod fact_scene;` to stage its own scenes.

use scenalog_engine::{evaluate, Options};
use scenalog_facts::catalog::{self, ColType};
use scenalog_facts::relation::{Column, Constraint, RelationData, Request, Value};
use scenalog_facts::scene::{is_construction_category, is_vehicle_category};
use scenalog_facts::{LaneId, TrackId};
use scenalog_rules::ast::{Clause, Expr, ExprKind};
use scenalog_rules::{check, parse, CheckOptions, CheckedProgram, Severity};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

pub fn program(name: &str) -> CheckedProgram {
    let path = root().join("rules/library").join(format!("{name}.dl"));
    let src = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    match check(&src, &CheckOptions::default()).program {
        Some(p) => p,
        None => panic!("{name}.dl does not check"),
    }
}

/// A number literal, possibly negated.
pub fn number(e: &Expr) -> Option<f64> {
    match &e.kind {
        ExprKind::Int(v) => Some(*v as f64),
        ExprKind::Float(v) => Some(*v),
        ExprKind::Neg(inner) => number(inner).map(|v| -v),
        _ => None,
    }
}

/// An integer literal, possibly negated.
pub fn integer(e: &Expr) -> Option<i64> {
    match &e.kind {
        ExprKind::Int(v) => Some(*v),
        ExprKind::Neg(inner) => integer(inner).map(|v| -v),
        _ => None,
    }
}

/// One fact argument as a value of a column of type `ty`.
pub fn value(e: &Expr, ty: ColType, fact: &str) -> Value {
    let v = match ty {
        ColType::Track => integer(e)
            .and_then(|v| u32::try_from(v).ok())
            .map(|v| Value::Track(TrackId(v))),
        ColType::Time => integer(e)
            .and_then(|v| u32::try_from(v).ok())
            .map(Value::Time),
        ColType::Lane => integer(e).map(|v| Value::Lane(LaneId(v))),
        ColType::Int => integer(e).map(Value::Int),
        ColType::Float => number(e).map(Value::Float),
        ColType::Str => match &e.kind {
            ExprKind::Str(s) => Some(Value::Str(s.as_str().into())),
            _ => None,
        },
    };
    v.unwrap_or_else(|| panic!("fact `{fact}`: argument {:?} is not a {ty}", e.kind))
}

/// The catalog relations of a fact scene, completed as the extractors would.
pub struct Facts {
    pub rows: BTreeMap<String, Vec<Vec<Value>>>,
    pub categories: BTreeMap<TrackId, BTreeSet<String>>,
}

impl Facts {
    pub fn parse(src: &str) -> Facts {
        let (prog, diags) = parse(src);
        if let Some(d) = diags.iter().find(|d| d.severity == Severity::Error) {
            panic!("fact scene does not parse: {} in\n{src}", d.message);
        }
        let mut rows: BTreeMap<String, Vec<Vec<Value>>> = BTreeMap::new();
        let mut push = |name: &str, row: Vec<Value>| {
            let rel = rows.entry(name.to_string()).or_default();
            if !rel.contains(&row) {
                rel.push(row);
            }
        };
        for Clause { head, body, span } in &prog.clauses {
            let text = &src[span.start..span.end];
            assert!(body.is_empty(), "not a ground fact: `{text}`");
            let spec = catalog::relation(&head.pred)
                .unwrap_or_else(|| panic!("`{text}`: `{}` is not in the catalog", head.pred));
            assert_eq!(spec.arity(), head.args.len(), "`{text}`: wrong arity");
            let row: Vec<Value> = head
                .args
                .iter()
                .zip(spec.types())
                .map(|(e, ty)| value(e, ty, text))
                .collect();
            if let (true, [Value::Track(x), Value::Str(c)]) = (spec.name == "category", &row[..]) {
                if is_vehicle_category(c) {
                    push(
                        "category",
                        vec![Value::Track(*x), Value::Str("VEHICLE".into())],
                    );
                }
                if is_construction_category(c) {
                    push(
                        "category",
                        vec![Value::Track(*x), Value::Str("CONSTRUCTION".into())],
                    );
                }
                push("category", vec![Value::Track(*x), Value::Str("ANY".into())]);
                if &**c == "EGO_VEHICLE" {
                    push("ego", vec![Value::Track(*x)]);
                }
            }
            if spec.name == "near" || spec.name == "heading_relative" {
                let mut mirror = row.clone();
                mirror.swap(0, 1);
                push(spec.name, mirror);
            }
            push(spec.name, row);
        }
        let mut categories: BTreeMap<TrackId, BTreeSet<String>> = BTreeMap::new();
        for r in rows.get("category").into_iter().flatten() {
            if let [Value::Track(x), Value::Str(c)] = &r[..] {
                categories.entry(*x).or_default().insert(c.to_string());
            }
        }
        for (name, rel) in &rows {
            for r in rel {
                for v in r {
                    if let Value::Track(t) = v {
                        assert!(
                            categories.contains_key(t),
                            "track {} in `{name}` has no category fact",
                            t.0
                        );
                    }
                }
            }
        }
        Facts { rows, categories }
    }

    pub fn holds(&self, v: &Value, c: &Constraint) -> bool {
        let num = match v {
            Value::Float(x) => Some(*x),
            Value::Int(x) => Some(*x as f64),
            Value::Time(x) => Some(f64::from(*x)),
            _ => None,
        };
        match c {
            Constraint::Eq(w) => v == w,
            Constraint::OneOf(ws) => ws.contains(v),
            Constraint::Category(cat) => match v {
                Value::Track(t) => self.categories.get(t).is_some_and(|cs| cs.contains(&**cat)),
                _ => panic!("category constraint on a non-track value {v:?}"),
            },
            Constraint::Lt(b) => num.is_some_and(|x| x < *b),
            Constraint::Le(b) => num.is_some_and(|x| x <= *b),
            Constraint::Gt(b) => num.is_some_and(|x| x > *b),
            Constraint::Ge(b) => num.is_some_and(|x| x >= *b),
            Constraint::Triples(_) => panic!("a Triples constraint applies to a row, not a value"),
        }
    }

    /// Whether `row` satisfies constraint `c` on column `i` (`Triples` on columns i..i+3).
    pub fn row_holds(&self, row: &[Value], i: usize, c: &Constraint) -> bool {
        match c {
            Constraint::Triples(ts) => match (row.get(i), row.get(i + 1), row.get(i + 2)) {
                (Some(Value::Track(x)), Some(Value::Track(y)), Some(Value::Time(t))) => {
                    ts.binary_search(&(*x, *y, *t)).is_ok()
                }
                other => panic!("Triples on columns that are not (track, track, time): {other:?}"),
            },
            _ => row.get(i).is_some_and(|v| self.holds(v, c)),
        }
    }

    /// The rows of the requested relation that satisfy every constraint, as columns.
    pub fn provide(&self, r: &Request) -> Result<RelationData, String> {
        let spec = catalog::relation(&r.name)
            .ok_or_else(|| format!("`{}` is not in the catalog", r.name))?;
        let mut columns: Vec<Column> = spec.types().into_iter().map(Column::empty).collect();
        let kept = self.rows.get(&r.name).into_iter().flatten().filter(|row| {
            r.constraints
                .iter()
                .all(|(i, c)| self.row_holds(row, *i, c))
        });
        for row in kept {
            for (col, v) in columns.iter_mut().zip(row) {
                match (col, v) {
                    (Column::Track(c), Value::Track(x)) => c.push(*x),
                    (Column::Time(c), Value::Time(x)) => c.push(*x),
                    (Column::Lane(c), Value::Lane(x)) => c.push(*x),
                    (Column::Str(c), Value::Str(x)) => c.push(x.clone()),
                    (Column::Float(c), Value::Float(x)) => c.push(*x),
                    (Column::Int(c), Value::Int(x)) => c.push(*x),
                    (c, v) => return Err(format!("{}: {v:?} in a {} column", r.name, c.ty())),
                }
            }
        }
        Ok(RelationData {
            name: r.name.clone(),
            columns,
        })
    }
}

/// What a program found: `referred` as (track, frame), `related` as (track, other, frame).
#[derive(Debug, PartialEq, Default)]
pub struct Found {
    pub referred: BTreeSet<(u32, u32)>,
    pub related: BTreeSet<(u32, u32, u32)>,
}

pub fn track(v: &Value) -> u32 {
    match v {
        Value::Track(t) => t.0,
        other => panic!("not a track: {other:?}"),
    }
}

pub fn frame(v: &Value) -> u32 {
    match v {
        Value::Time(t) => *t,
        other => panic!("not a time: {other:?}"),
    }
}

/// Evaluates library program `name` on the fact scene `facts`.
pub fn run(name: &str, facts: &str) -> Found {
    let p = program(name);
    let facts = Facts::parse(facts);
    let mut provider = |r: &Request| facts.provide(r);
    let ev =
        evaluate(&p, &mut provider, &Options::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
    let referred = ev
        .tuples("referred")
        .unwrap_or_default()
        .iter()
        .map(|t| (track(&t[0]), frame(&t[1])))
        .collect();
    let related = ev
        .tuples("related")
        .unwrap_or_default()
        .iter()
        .map(|t| (track(&t[0]), track(&t[1]), frame(&t[2])))
        .collect();
    Found { referred, related }
}

/// Asserts that `name` finds exactly `referred` and `related` on `facts`.
#[track_caller]
pub fn finds(name: &str, facts: &str, referred: &[(u32, u32)], related: &[(u32, u32, u32)]) {
    let want = Found {
        referred: referred.iter().copied().collect(),
        related: related.iter().copied().collect(),
    };
    assert_eq!(run(name, facts), want, "{name} on\n{facts}");
}

/// Asserts that `name` finds nothing on `facts`.
#[track_caller]
pub fn nothing(name: &str, facts: &str) {
    finds(name, facts, &[], &[]);
}

/// `base` with `from` replaced by `to`; `from` must occur in `base`.
#[track_caller]
pub fn swap(base: &str, from: &str, to: &str) -> String {
    assert!(base.contains(from), "`{from}` is not in\n{base}");
    base.replace(from, to)
}

/// The rows of a provided relation, as values.
pub fn provided(f: &Facts, r: &Request) -> Vec<Vec<Value>> {
    let d = f.provide(r).unwrap_or_else(|e| panic!("{e}"));
    (0..d.len()).filter_map(|i| d.row(i)).collect()
}
