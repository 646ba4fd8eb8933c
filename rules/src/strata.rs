//! Stratification: the predicate dependency graph, its strongly connected components (Tarjan),
//! and strata in evaluation order. Catalog relations are inputs and get no stratum.

use std::collections::BTreeMap;

use scenalog_facts::catalog;

use crate::ast::{Literal, Program, Span};
use crate::diagnostics::{self, error};
use crate::{Diagnostic, Stratum};

/// How a rule's head depends on a body predicate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EdgeKind {
    /// Through a positive atom.
    Positive,
    /// Through a negated atom.
    Negative,
    /// Through an atom inside an aggregate.
    Aggregate,
}

/// One dependency: the head predicate `from` of clause `clause` uses `to` at `span`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DepEdge {
    /// Index of the head predicate in [`DepGraph::preds`].
    pub from: usize,
    /// Index of the body predicate in [`DepGraph::preds`].
    pub to: usize,
    /// Positive, negative or aggregate.
    pub kind: EdgeKind,
    /// Index of the clause in `program.clauses`.
    pub clause: usize,
    /// Span of the body literal.
    pub span: Span,
}

/// The dependency graph over derived predicates (catalog relations are left out).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct DepGraph {
    /// Derived predicates, in order of first appearance as a head or declaration.
    pub preds: Vec<String>,
    /// Dependencies between them.
    pub edges: Vec<DepEdge>,
}

impl DepGraph {
    /// Index of a predicate.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.preds.iter().position(|p| p == name)
    }
}

/// Builds the dependency graph of a program's derived predicates.
pub fn dependency_graph(program: &Program) -> DepGraph {
    let mut preds: Vec<String> = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    let mut add = |name: &str, preds: &mut Vec<String>| {
        if catalog::relation(name).is_none() && seen.insert(name.to_string()) {
            preds.push(name.to_string());
        }
    };
    for d in &program.decls {
        add(&d.name, &mut preds);
    }
    for c in &program.clauses {
        add(&c.head.pred, &mut preds);
    }
    let index: BTreeMap<&str, usize> = preds
        .iter()
        .enumerate()
        .map(|(i, p)| (p.as_str(), i))
        .collect();
    let mut edges = Vec::new();
    for (ci, c) in program.clauses.iter().enumerate() {
        let Some(&from) = index.get(c.head.pred.as_str()) else {
            continue;
        };
        let mut stack: Vec<(&Literal, bool)> = c.body.iter().map(|l| (l, false)).collect();
        stack.reverse();
        while let Some((lit, in_agg)) = stack.pop() {
            let (atom, kind) = match lit {
                Literal::Pos(a) => (
                    a,
                    if in_agg {
                        EdgeKind::Aggregate
                    } else {
                        EdgeKind::Positive
                    },
                ),
                Literal::Neg(a, _) => (a, EdgeKind::Negative),
                Literal::Cmp(_) => continue,
                Literal::Agg(g) => {
                    for l in g.body.iter().rev() {
                        stack.push((l, true));
                    }
                    continue;
                }
            };
            if let Some(&to) = index.get(atom.pred.as_str()) {
                edges.push(DepEdge {
                    from,
                    to,
                    kind,
                    clause: ci,
                    span: lit.span(),
                });
            }
        }
    }
    DepGraph { preds, edges }
}

/// Strongly connected components in dependency order: every component comes after the
/// components it depends on (Tarjan's algorithm, iterative).
pub fn sccs(graph: &DepGraph) -> Vec<Vec<usize>> {
    let n = graph.preds.len();
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n];
    for e in &graph.edges {
        adj[e.from].push(e.to);
    }
    const UNSEEN: usize = usize::MAX;
    let mut index = vec![UNSEEN; n];
    let mut low = vec![0; n];
    let mut on_stack = vec![false; n];
    let mut stack = Vec::new();
    let mut next = 0;
    let mut out = Vec::new();
    for root in 0..n {
        if index[root] != UNSEEN {
            continue;
        }
        // (node, next child position)
        let mut call: Vec<(usize, usize)> = vec![(root, 0)];
        index[root] = next;
        low[root] = next;
        next += 1;
        stack.push(root);
        on_stack[root] = true;
        while let Some(&mut (v, ref mut child)) = call.last_mut() {
            if *child < adj[v].len() {
                let w = adj[v][*child];
                *child += 1;
                if index[w] == UNSEEN {
                    index[w] = next;
                    low[w] = next;
                    next += 1;
                    stack.push(w);
                    on_stack[w] = true;
                    call.push((w, 0));
                } else if on_stack[w] {
                    low[v] = low[v].min(index[w]);
                }
            } else {
                call.pop();
                if let Some(&(parent, _)) = call.last() {
                    low[parent] = low[parent].min(low[v]);
                }
                if low[v] == index[v] {
                    let mut comp = Vec::new();
                    while let Some(w) = stack.pop() {
                        on_stack[w] = false;
                        comp.push(w);
                        if w == v {
                            break;
                        }
                    }
                    comp.sort_unstable();
                    out.push(comp);
                }
            }
        }
    }
    out
}

/// Strata in evaluation order, and an E0301/E0302 diagnostic for every negation or aggregate
/// inside a recursive cycle.
pub fn stratify(program: &Program) -> (Vec<Stratum>, Vec<Diagnostic>) {
    let graph = dependency_graph(program);
    let comps = sccs(&graph);
    let mut comp_of = vec![0; graph.preds.len()];
    for (ci, comp) in comps.iter().enumerate() {
        for &p in comp {
            comp_of[p] = ci;
        }
    }
    let mut diags = Vec::new();
    for e in &graph.edges {
        if e.kind == EdgeKind::Positive || comp_of[e.from] != comp_of[e.to] {
            continue;
        }
        diags.push(cycle_diagnostic(program, &graph, &comp_of, e));
    }
    let index: std::collections::HashMap<&str, usize> = graph
        .preds
        .iter()
        .enumerate()
        .map(|(i, p)| (p.as_str(), i))
        .collect();
    let clause_pred: Vec<Option<usize>> = program
        .clauses
        .iter()
        .map(|c| index.get(c.head.pred.as_str()).copied())
        .collect();
    // Each edge and each clause is visited once (not once per component): 100k rules check in
    // linear time.
    let mut self_loop = vec![false; graph.preds.len()];
    for e in graph.edges.iter().filter(|e| e.from == e.to) {
        self_loop[e.from] = true;
    }
    let mut clauses_of: Vec<Vec<usize>> = vec![Vec::new(); comps.len()];
    for (i, p) in clause_pred.iter().enumerate() {
        if let Some(&p) = p.as_ref() {
            clauses_of[comp_of[p]].push(i);
        }
    }
    let mut strata = Vec::new();
    for (comp, clauses) in comps.iter().zip(clauses_of) {
        let recursive = comp.len() > 1 || self_loop[comp[0]];
        strata.push(Stratum {
            predicates: comp.iter().map(|&i| graph.preds[i].clone()).collect(),
            clauses,
            recursive,
        });
    }
    (strata, diags)
}

/// E0301/E0302 for `e`, naming the cycle `from -(!)-> to -> … -> from` rule by rule.
fn cycle_diagnostic(
    program: &Program,
    graph: &DepGraph,
    comp_of: &[usize],
    e: &DepEdge,
) -> Diagnostic {
    // Shortest path to -> … -> from inside the component (BFS), as edge indices.
    let n = graph.preds.len();
    let mut prev: Vec<Option<usize>> = vec![None; n];
    let mut seen = vec![false; n];
    let mut queue = std::collections::VecDeque::new();
    seen[e.to] = true;
    queue.push_back(e.to);
    while let Some(v) = queue.pop_front() {
        if v == e.from {
            break;
        }
        for (ei, x) in graph.edges.iter().enumerate() {
            if x.from == v && !seen[x.to] && comp_of[x.to] == comp_of[e.from] {
                seen[x.to] = true;
                prev[x.to] = Some(ei);
                queue.push_back(x.to);
            }
        }
    }
    let mut path = Vec::new();
    let mut v = e.from;
    while v != e.to {
        let Some(ei) = prev[v] else { break };
        path.push(ei);
        v = graph.edges[ei].from;
    }
    path.reverse();
    let name = |i: usize| graph.preds[i].as_str();
    let (code, what) = match e.kind {
        EdgeKind::Negative => (diagnostics::NEGATION_CYCLE, "negation"),
        _ => (diagnostics::AGGREGATE_CYCLE, "aggregation"),
    };
    let used = match e.kind {
        EdgeKind::Negative => format!("`!{}`", name(e.to)),
        _ => format!("an aggregate over `{}`", name(e.to)),
    };
    let mut cycle = format!("`{}` uses {used}", name(e.from));
    for &ei in &path {
        let x = &graph.edges[ei];
        cycle.push_str(&format!(", `{}` uses `{}`", name(x.from), name(x.to)));
    }
    let mut d = error(
        code,
        e.span,
        format!("{what} through recursion: {cycle}"),
    )
    .with_hint(format!(
        "a predicate cannot depend on {} itself; compute the {what} over a predicate that does not depend on `{}`",
        if e.kind == EdgeKind::Negative { "the negation of" } else { "an aggregate over" },
        name(e.from)
    ));
    d = d.with_related(
        program.clauses[e.clause].span,
        format!("`{}` uses {used} in this rule", name(e.from)),
    );
    for &ei in &path {
        let x = &graph.edges[ei];
        d = d.with_related(
            program.clauses[x.clause].span,
            format!("`{}` uses `{}` in this rule", name(x.from), name(x.to)),
        );
    }
    d
}
