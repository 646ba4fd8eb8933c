//! Property: printing a program and parsing it back gives the same AST (spans aside), and printing
//! that again gives the same text.

use proptest::prelude::*;
use scenalog_facts::catalog::ColType;
use scenalog_rules::ast::*;
use scenalog_rules::{parse, print_program};

/// Sets every span to the default, so ASTs compare by structure.
fn erase(p: &mut Program) {
    for d in &mut p.decls {
        d.span = Span::default();
        d.name_span = Span::default();
    }
    for c in &mut p.clauses {
        c.span = Span::default();
        erase_atom(&mut c.head);
        erase_body(&mut c.body);
    }
}

fn erase_atom(a: &mut Atom) {
    a.span = Span::default();
    a.pred_span = Span::default();
    a.args.iter_mut().for_each(erase_expr);
}

fn erase_body(body: &mut [Literal]) {
    for l in body {
        match l {
            Literal::Pos(a) => erase_atom(a),
            Literal::Neg(a, s) => {
                erase_atom(a);
                *s = Span::default();
            }
            Literal::Cmp(c) => {
                c.span = Span::default();
                erase_expr(&mut c.lhs);
                erase_expr(&mut c.rhs);
            }
            Literal::Agg(g) => {
                g.span = Span::default();
                erase_expr(&mut g.result);
                if let Some(t) = &mut g.target {
                    erase_expr(t);
                }
                erase_body(&mut g.body);
            }
        }
    }
}

fn erase_expr(e: &mut Expr) {
    e.span = Span::default();
    match &mut e.kind {
        ExprKind::Neg(x) => erase_expr(x),
        ExprKind::Binary(_, a, b) => {
            erase_expr(a);
            erase_expr(b);
        }
        ExprKind::Call(_, args) => args.iter_mut().for_each(erase_expr),
        _ => {}
    }
}

fn ex(kind: ExprKind) -> Expr {
    Expr {
        kind,
        span: Span::default(),
    }
}

fn pred_name() -> impl Strategy<Value = String> {
    "[a-z][a-z0-9_]{0,6}".prop_filter("builtin functions are not predicates", |s| {
        !matches!(s.as_str(), "abs" | "min" | "max")
    })
}

fn var_name() -> impl Strategy<Value = String> {
    prop_oneof!["[A-Z][A-Za-z0-9_]{0,5}", "_[A-Za-z0-9_]{1,5}"]
}

fn expr() -> impl Strategy<Value = Expr> {
    let leaf = prop_oneof![
        var_name().prop_map(|v| ex(ExprKind::Var(v))),
        Just(ex(ExprKind::Wildcard)),
        any::<String>().prop_map(|s| ex(ExprKind::Str(s))),
        any::<i64>().prop_map(|i| ex(ExprKind::Int(i))),
        any::<f64>()
            .prop_filter("finite", |f| f.is_finite())
            .prop_map(|f| ex(ExprKind::Float(f))),
        (
            -1.0e6..1.0e6f64,
            prop_oneof![
                Just("m"),
                Just("km/h"),
                Just("rad/s"),
                Just("s"),
                Just("m/s2")
            ]
        )
            .prop_map(|(value, unit)| ex(ExprKind::Quantity(Quantity {
                value,
                unit: unit.to_string(),
                read_as: None,
            }))),
    ];
    leaf.prop_recursive(4, 24, 3, |inner| {
        let op = prop_oneof![
            Just(BinOp::Add),
            Just(BinOp::Sub),
            Just(BinOp::Mul),
            Just(BinOp::Div),
            Just(BinOp::Mod),
            Just(BinOp::Pow)
        ];
        prop_oneof![
            inner.clone().prop_map(|e| ex(ExprKind::Neg(Box::new(e)))),
            (op, inner.clone(), inner.clone()).prop_map(|(o, a, b)| ex(ExprKind::Binary(
                o,
                Box::new(a),
                Box::new(b)
            ))),
            inner
                .clone()
                .prop_map(|e| ex(ExprKind::Call(Func::Abs, vec![e]))),
            (
                prop_oneof![Just(Func::Min), Just(Func::Max)],
                inner.clone(),
                inner
            )
                .prop_map(|(f, a, b)| ex(ExprKind::Call(f, vec![a, b]))),
        ]
    })
}

fn atom() -> impl Strategy<Value = Atom> {
    (pred_name(), prop::collection::vec(expr(), 0..4)).prop_map(|(pred, args)| Atom {
        pred,
        pred_span: Span::default(),
        args,
        span: Span::default(),
    })
}

fn cmp_op() -> impl Strategy<Value = CmpOp> {
    prop_oneof![
        Just(CmpOp::Lt),
        Just(CmpOp::Le),
        Just(CmpOp::Gt),
        Just(CmpOp::Ge),
        Just(CmpOp::Eq),
        Just(CmpOp::Ne)
    ]
}

fn literal() -> impl Strategy<Value = Literal> {
    let simple = prop_oneof![
        atom().prop_map(Literal::Pos),
        atom().prop_map(|a| Literal::Neg(a, Span::default())),
        (cmp_op(), expr(), expr()).prop_map(|(op, lhs, rhs)| Literal::Cmp(Comparison {
            op,
            lhs,
            rhs,
            span: Span::default()
        })),
    ];
    simple.prop_recursive(2, 12, 3, |inner| {
        let func = prop_oneof![
            Just(AggFunc::Count),
            Just(AggFunc::Min),
            Just(AggFunc::Max),
            Just(AggFunc::Sum)
        ];
        (func, expr(), expr(), prop::collection::vec(inner, 1..3)).prop_map(
            |(func, result, target, body)| {
                Literal::Agg(Aggregate {
                    result,
                    func,
                    target: (func != AggFunc::Count).then_some(target),
                    body,
                    span: Span::default(),
                })
            },
        )
    })
}

fn col_type() -> impl Strategy<Value = ColType> {
    prop_oneof![
        Just(ColType::Track),
        Just(ColType::Time),
        Just(ColType::Lane),
        Just(ColType::Str),
        Just(ColType::Float),
        Just(ColType::Int)
    ]
}

fn program() -> impl Strategy<Value = Program> {
    let decl = (
        pred_name(),
        prop::collection::vec((var_name(), col_type()), 0..4),
    )
        .prop_map(|(name, columns)| Decl {
            name,
            name_span: Span::default(),
            units: columns
                .iter()
                .map(|(_, t)| (*t == ColType::Float).then(|| "m/s".to_string()))
                .collect(),
            columns,
            span: Span::default(),
        });
    let clause = (atom(), prop::collection::vec(literal(), 0..4)).prop_map(|(head, body)| Clause {
        head,
        body,
        span: Span::default(),
    });
    (
        prop::option::of("[a-zA-Z0-9 ,.'()-]{0,30}".prop_map(|s| s.trim().to_string())),
        prop::collection::vec(decl, 0..3),
        prop::collection::vec(clause, 0..5),
    )
        .prop_map(|(description, decls, clauses)| Program {
            description,
            decls,
            clauses,
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn print_parse_round_trip(ast in program()) {
        let text = print_program(&ast);
        let (mut back, diags) = parse(&text);
        prop_assert!(diags.is_empty(), "{text}\n{diags:#?}");
        prop_assert_eq!(print_program(&back), text.clone());
        erase(&mut back);
        prop_assert_eq!(back, ast, "{}", text);
    }
}

#[test]
fn floats_print_so_they_reparse_as_the_same_float() {
    for f in [
        0.0,
        -0.0,
        1.0,
        0.1,
        1e300,
        5e-324,
        -2.5,
        123456789.0,
        f64::MAX,
        f64::MIN_POSITIVE,
    ] {
        let text = scenalog_rules::printer::float_text(f);
        assert!(text.contains(['.', 'e']), "{text}");
        let src = format!("p(X) :- q(X), X < {text}.");
        let (p, d) = parse(&src);
        assert!(d.is_empty(), "{d:#?}");
        let Literal::Cmp(c) = &p.clauses[0].body[1] else {
            panic!("not a comparison: {src}");
        };
        assert_eq!(c.rhs.kind, ExprKind::Float(f), "{text}");
    }
}
