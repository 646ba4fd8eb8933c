//! The parser on hand-written programs: every construct, spans, and recovery.

use scenalog_rules::ast::*;
use scenalog_rules::{check, parse, CheckOptions};

fn text(src: &str, s: Span) -> &str {
    &src[s.start..s.end]
}

#[test]
fn every_construct_parses_with_spans() {
    let src = "// description:  turning bus \n% line comment\n/* block\ncomment */\n.decl near_bus(X: track, T: time, D: float)\nfact(\"a\", -3, 2.5e-1).\nnear_bus(X, T, D) :- category(X, \"BUS\"), not stationary(X), !ego(X), near(X, _, T, D), D <= 2 + 3 * -1.\n";
    let (p, d) = parse(src);
    assert!(d.is_empty(), "{d:#?}");
    assert_eq!(p.description.as_deref(), Some("turning bus"));
    assert_eq!(p.decls.len(), 1);
    assert_eq!(
        p.decls[0].columns[2],
        ("D".to_string(), scenalog_facts::catalog::ColType::Float)
    );
    assert_eq!(
        text(src, p.decls[0].span),
        ".decl near_bus(X: track, T: time, D: float)"
    );
    let fact = &p.clauses[0];
    assert!(fact.is_fact());
    assert_eq!(fact.head.args[1].kind, ExprKind::Int(-3));
    assert_eq!(fact.head.args[2].kind, ExprKind::Float(0.25));
    assert_eq!(text(src, fact.span), "fact(\"a\", -3, 2.5e-1).");
    let c = &p.clauses[1];
    assert_eq!(c.body.len(), 5);
    let Literal::Neg(a, s) = &c.body[1] else {
        panic!("not p")
    };
    assert_eq!(a.pred, "stationary");
    assert_eq!(text(src, *s), "not stationary(X)");
    let Literal::Neg(_, s) = &c.body[2] else {
        panic!("!p")
    };
    assert_eq!(text(src, *s), "!ego(X)");
    let Literal::Cmp(cmp) = &c.body[4] else {
        panic!("comparison")
    };
    assert_eq!(cmp.op, CmpOp::Le);
    assert_eq!(text(src, cmp.rhs.span), "2 + 3 * -1");
    // 2 + (3 * -1): multiplication binds tighter.
    let ExprKind::Binary(BinOp::Add, _, r) = &cmp.rhs.kind else {
        panic!("{:?}", cmp.rhs)
    };
    assert!(matches!(r.kind, ExprKind::Binary(BinOp::Mul, _, _)));
    assert_eq!(text(src, c.head.pred_span), "near_bus");
}

#[test]
fn aggregates_and_builtin_functions() {
    let src = "p(X, N, M, S) :- q(X), N = count : { r(X, Y) }, M = min D : { r(X, D) }, S = sum abs(D) * 2 : { r(X, D) }, K = max(N, M), K > 0.\n";
    let (p, d) = parse(src);
    assert!(d.is_empty(), "{d:#?}");
    let body = &p.clauses[0].body;
    let Literal::Agg(g) = &body[1] else {
        panic!("count")
    };
    assert_eq!((g.func, g.target.is_none()), (AggFunc::Count, true));
    assert_eq!(text(src, g.span), "N = count : { r(X, Y) }");
    let Literal::Agg(g) = &body[2] else {
        panic!("min")
    };
    assert_eq!(g.func, AggFunc::Min);
    let Literal::Agg(g) = &body[3] else {
        panic!("sum")
    };
    assert_eq!(g.func, AggFunc::Sum);
    assert_eq!(
        g.target.as_ref().map(|t| text(src, t.span)),
        Some("abs(D) * 2")
    );
    let Literal::Cmp(c) = &body[4] else {
        panic!("max(N, M) is a function here")
    };
    assert!(matches!(c.rhs.kind, ExprKind::Call(Func::Max, _)));
}

#[test]
fn helpful_syntax_hints() {
    let d = &check(
        "referred(X, T) :- present(X, T), X == 3.\n",
        &CheckOptions::default(),
    )
    .diagnostics;
    assert_eq!(d[0].code, "E0001");
    assert_eq!(d[0].hint.as_deref(), Some("equality is a single `=`"));
    let d = &check(
        "referred(X, T) :- present(X, T), category(X, VEHICLE).\n",
        &CheckOptions::default(),
    )
    .diagnostics;
    assert_eq!(d[0].code, "W0501");
    assert!(d[0]
        .hint
        .as_deref()
        .unwrap_or("")
        .contains("quote it: \"VEHICLE\""));
    let d = &check("referred(X, T) :- present(X, T)", &CheckOptions::default()).diagnostics;
    assert_eq!(d[0].hint.as_deref(), Some("every clause ends with `.`"));
}

#[test]
fn a_stray_token_between_clauses_does_not_swallow_the_next_clause() {
    let src = "p(X) :- ego(X).. # q(X) :- ego(X).\nreferred(X, T) :- p(X), q(X), present(X, T).\n";
    let (prog, d) = parse(src);
    assert_eq!(d.len(), 1, "{d:#?}");
    let heads: Vec<&str> = prog.clauses.iter().map(|c| c.head.pred.as_str()).collect();
    assert_eq!(heads, vec!["p", "q", "referred"]);
}

#[test]
fn a_run_of_stray_tokens_is_one_error() {
    let (prog, d) = parse("1 2 3 4 ) ( p(X) :- ego(X).");
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(prog.clauses.len(), 1);
    let (prog, d) = parse("1 2 3 4 .\np(X) :- ego(X). 5 q(X) :- ego(X).");
    assert_eq!(d.len(), 2, "a new run after a good clause: {d:#?}");
    assert_eq!(prog.clauses.len(), 2);
}

#[test]
fn modulo_is_mod_and_power_binds_tighter_than_a_sign() {
    use scenalog_rules::printer::print_expr;
    let (p, diags) =
        parse("r(A, B, C, D) :- n(X), A = X mod 3 * 2, B = -2 ^ 2, C = 2 ^ 3 ^ 2, D = 7 mod 2.\n");
    assert!(diags.is_empty(), "{diags:?}");
    let sides: Vec<String> = p.clauses[0]
        .body
        .iter()
        .filter_map(|l| match l {
            Literal::Cmp(c) => Some(print_expr(&c.rhs)),
            _ => None,
        })
        .collect();
    // `mod` is multiplicative and left-associative; `^` is right-associative and above `-`.
    assert_eq!(sides, ["X mod 3 * 2", "-(2 ^ 2)", "2 ^ 3 ^ 2", "7 mod 2"]);
    let Literal::Cmp(c) = &p.clauses[0].body[3] else {
        panic!("a comparison")
    };
    let ExprKind::Binary(BinOp::Pow, _, right) = &c.rhs.kind else {
        panic!("a power: {:?}", c.rhs)
    };
    assert!(matches!(right.kind, ExprKind::Binary(BinOp::Pow, ..)));
    // `%` stays a comment (Prolog's habit): what follows it on the line is not read.
    let (p, diags) = parse("r(X) :- n(X). % X mod 2\n");
    assert!(diags.is_empty() && p.clauses.len() == 1, "{diags:?}");
}
