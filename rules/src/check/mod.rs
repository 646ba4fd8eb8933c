//! The checks against the catalog: predicates and arity ([`preds`]), types ([`types`]), safety
//! and singleton variables ([`safety`]); stratification lives in [`crate::strata`].

pub mod preds;
pub mod safety;
pub mod types;

use std::collections::BTreeMap;

use scenalog_facts::catalog::{self, ColType};

use crate::ast::{Atom, Literal};
use crate::parser::parse_detailed;
use crate::{strata, CheckOptions, CheckOutcome, CheckedProgram, PredKind, PredicateInfo};

/// Parses and checks `source`; see [`crate::check()`].
pub fn check_source(source: &str, options: &CheckOptions) -> CheckOutcome {
    let parsed = parse_detailed(source);
    let mut diags = parsed.diagnostics;
    let program = parsed.program;
    let table = preds::collect(&program, &parsed.broken_heads, options, &mut diags);
    let inferred = types::infer(&program, &table, &mut diags);
    for c in &program.clauses {
        safety::check_clause(c, &mut diags);
    }
    let (strata, cycle_diags) = strata::stratify(&program);
    diags.extend(cycle_diags);
    diags.sort_by_key(|d| (d.span.start, d.span.end));
    diags.dedup();
    let has_error = diags.iter().any(|d| d.is_error());
    let program = if has_error {
        None
    } else {
        let mut predicates = BTreeMap::new();
        for (name, entry) in &table.preds {
            let types: Vec<ColType> = match entry.kind {
                PredKind::Catalog => catalog::relation(name)
                    .map(|r| r.types())
                    .unwrap_or_default(),
                PredKind::Derived => inferred.get(name).cloned().unwrap_or_default(),
            };
            predicates.insert(
                name.clone(),
                PredicateInfo {
                    name: name.clone(),
                    types,
                    kind: entry.kind,
                },
            );
        }
        Some(CheckedProgram {
            program,
            predicates,
            strata,
            warnings: diags.clone(),
        })
    };
    CheckOutcome {
        program,
        diagnostics: diags,
    }
}

/// Every atom of a clause's body, including inside aggregates, with whether it is negated.
pub(crate) fn body_atoms(body: &[Literal]) -> Vec<(&Atom, bool)> {
    let mut out = Vec::new();
    for l in body {
        match l {
            Literal::Pos(a) => out.push((a, false)),
            Literal::Neg(a, _) => out.push((a, true)),
            Literal::Cmp(_) => {}
            Literal::Agg(g) => out.extend(body_atoms(&g.body)),
        }
    }
    out
}
