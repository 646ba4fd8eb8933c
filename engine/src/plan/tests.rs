//! Tests of the planner: expressions, filters, narrowing and aggregates against the general
//! evaluator and hand-computed cases.

use super::*;
use crate::value::{enc_int, WIDTH};

#[test]
fn integer_expressions_agree_with_the_general_evaluator() {
    let slot = |s| Box::new(CExpr::Slot(s, ColType::Int));
    let exprs = [
        CExpr::Call(Func::Abs, vec![CExpr::Bin(BinOp::Sub, slot(0), slot(1))]),
        CExpr::Bin(BinOp::Sub, slot(1), slot(0)),
        CExpr::Bin(BinOp::Mul, slot(0), Box::new(CExpr::Const(V::Int(3)))),
        CExpr::Neg(Box::new(CExpr::Bin(BinOp::Div, slot(0), slot(1)))),
        CExpr::Bin(
            BinOp::Add,
            Box::new(CExpr::Slot(2, ColType::Time)),
            Box::new(CExpr::Const(V::Int(-20))),
        ),
    ];
    for (a, b) in [(5, 9), (-7, 3), (i64::MIN, 1), (i64::MAX, -1), (4, 0)] {
        let mut row = [0u64; WIDTH];
        row[0] = enc_int(a);
        row[1] = enc_int(b);
        row[2] = 17;
        for e in &exprs {
            let want = e.eval(&row).and_then(|v| match v {
                V::Int(i) => Some(i),
                _ => None,
            });
            let Some(ie) = IExpr::from(e) else {
                panic!("{e:?} is an integer expression");
            };
            assert_eq!(ie.eval(&row), want, "{e:?} on {a}, {b}");
        }
    }
}

#[test]
fn compiled_differences_agree_with_the_general_comparison() {
    let mut seed = 5u64;
    let mut next = || crate::stratum::join::tests::lcg(&mut seed);
    let ops = [
        CmpOp::Lt,
        CmpOp::Le,
        CmpOp::Gt,
        CmpOp::Ge,
        CmpOp::Eq,
        CmpOp::Ne,
    ];
    let edges = [i64::MIN, i64::MIN + 1, -1, 0, 1, i64::MAX - 1, i64::MAX];
    let slot = |s| Box::new(CExpr::Slot(s, ColType::Int));
    for case in 0..20_000 {
        let mut pick = |small: bool| -> i64 {
            let r = next();
            match r % 4 {
                0 => edges[(r / 4) as usize % edges.len()],
                _ if small => (r / 4 % 41) as i64 - 20,
                _ => ((r as i64) << 29) - (1i64 << 59),
            }
        };
        let (x, y, c) = (pick(case % 2 == 0), pick(case % 2 == 0), pick(true));
        let op = ops[case % ops.len()];
        let diff = CExpr::Bin(BinOp::Sub, slot(0), slot(1));
        let e = if case % 3 == 0 {
            CExpr::Call(Func::Abs, vec![diff])
        } else {
            diff
        };
        let k = CExpr::Const(V::Int(c));
        // Both sides: `e op c` and `c op e`.
        let (l, r) = if case % 5 == 0 { (k, e) } else { (e, k) };
        let compiled = cmp_filter(op, l.clone(), r.clone());
        assert!(matches!(compiled, Filter::CmpDiff { .. }), "{compiled:?}");
        let general = Filter::Cmp(op, l, r);
        let mut row = [0u64; WIDTH];
        row[0] = enc_int(x);
        row[1] = enc_int(y);
        assert_eq!(
            apply(&[compiled], row).is_some(),
            apply(&[general], row).is_some(),
            "{op:?} on {x}, {y}, {c} (case {case})"
        );
    }
}

#[test]
fn words_agree_with_evaluating_then_encoding() {
    let mut seed = 7u64;
    let mut next = || crate::stratum::join::tests::lcg(&mut seed);
    let edges = [i64::MIN, i64::MIN + 1, -1, 0, 1, i64::MAX - 1, i64::MAX];
    let types = [ColType::Int, ColType::Time, ColType::Float, ColType::Str];
    for case in 0..20_000usize {
        let r = next();
        let c = match r % 3 {
            0 => edges[(r / 3) as usize % edges.len()],
            _ => (r / 3 % 21) as i64 - 10,
        };
        let from = types[case % types.len()];
        let to = types[(case / 4) % types.len()];
        let op = if case % 2 == 0 {
            BinOp::Add
        } else {
            BinOp::Sub
        };
        let slot = Box::new(CExpr::Slot(0, from));
        let e = match case % 3 {
            0 => CExpr::Slot(0, from),
            1 => CExpr::Bin(op, slot, Box::new(CExpr::Const(V::Int(c)))),
            _ => CExpr::Bin(op, Box::new(CExpr::Const(V::Int(c))), slot),
        };
        // A stored word of the slot's type: times fit in u32, floats are not NaN.
        let w = next() << 31 ^ next();
        let word = match from {
            ColType::Int => enc_int(edges.get(w as usize % 9).copied().unwrap_or(w as i64)),
            ColType::Time => w % (1 << 32),
            ColType::Float => crate::value::enc_float((w % 1000) as f64 - 500.5),
            _ => w % 50,
        };
        let mut row = [0u64; WIDTH];
        row[0] = word;
        let want = e.eval(&row).map(|v| encode(v, to));
        assert_eq!(e.word(&row, to), want, "{e:?} into {to:?} on {word}");
    }
}

#[test]
fn strict_windows_hold_every_value_their_comparisons_accept() {
    let mut seed = 13u64;
    let mut next = || crate::stratum::join::tests::lcg(&mut seed);
    let ops = [CmpOp::Lt, CmpOp::Le, CmpOp::Gt, CmpOp::Ge, CmpOp::Eq];
    for case in 0..10_000usize {
        // Int columns (any sign) or time columns (from 0, stored as the number itself).
        let ty = if case % 2 == 0 {
            ColType::Int
        } else {
            ColType::Time
        };
        let (word, xs, y) = match ty {
            ColType::Int => (
                enc_int as fn(i64) -> u64,
                -45..=45,
                (next() % 41) as i64 - 20,
            ),
            _ => (
                (|x: i64| x as u64) as fn(i64) -> u64,
                0..=45,
                (next() % 41) as i64,
            ),
        };
        let slot = |s| Box::new(CExpr::Slot(s, ty));
        let op = ops[(case / 2) % ops.len()];
        let c = (next() % 21) as i64 - 10;
        let k = Box::new(CExpr::Const(V::Int(c)));
        // Slot 0 is bound before the atom; slot 1 (x) is the atom's new column.
        let shape = (case / 10) % 4;
        let (l, r) = match shape {
            0 => (CExpr::Slot(1, ty), CExpr::Slot(0, ty)),
            1 => (CExpr::Bin(BinOp::Sub, slot(1), slot(0)), (*k).clone()),
            2 => (CExpr::Bin(BinOp::Sub, slot(0), slot(1)), (*k).clone()),
            _ => (
                CExpr::Call(Func::Abs, vec![CExpr::Bin(BinOp::Sub, slot(1), slot(0))]),
                (*k).clone(),
            ),
        };
        let cmps = [(op, l.clone(), r.clone())];
        let Some((n, used)) = narrowing(&[(0, 1)], &[ty], &cmps, 1) else {
            continue;
        };
        assert_eq!(used, vec![0]);
        let mut row = [0u64; WIDTH];
        row[0] = word(y);
        let range = n.range(&row);
        for x in xs {
            row[1] = word(x);
            let passes = apply(&[Filter::Cmp(op, l.clone(), r.clone())], row).is_some();
            let inside = range.is_some_and(|(lo, hi)| (lo..=hi).contains(&word(x)));
            assert!(
                !passes || inside,
                "{l:?} {op:?} {r:?}: x = {x}, y = {y}, {range:?}"
            );
            // Strict bounds step inward, so on ints and times the window is exact (but
            // for `abs(x - y) = c`, two values at the ends of a range).
            if !(shape == 3 && op == CmpOp::Eq) {
                assert_eq!(
                    passes, inside,
                    "{l:?} {op:?} {r:?}: x = {x}, y = {y}, {range:?}"
                );
            }
        }
    }
}
