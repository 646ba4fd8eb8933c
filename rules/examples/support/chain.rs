//! The generated programs the checker's scale is measured on (`benches/check.rs`,
//! `examples/check_scale.rs`).

/// `n` helper rules, each using the next (so `n` strata), and the `referred` rule.
pub fn chain_program(n: usize) -> String {
    let mut src = String::new();
    for i in 0..n {
        src.push_str(&format!(
            "h{i}(V, T) :- h{}(V, T), speed(V, T, S), S > 0.5 m/s.\n",
            i + 1
        ));
    }
    src.push_str(&format!(
        "h{n}(V, T) :- present(V, T).\nreferred(V, T) :- h0(V, T).\n"
    ));
    src
}

/// One `referred` rule whose body holds `n` atoms, each binding a variable of its own
/// (`present(X0, T), present(X1, T), …`).
pub fn wide_body_program(n: usize) -> String {
    let atoms: Vec<String> = (0..n).map(|i| format!("present(X{i}, T)")).collect();
    format!("referred(X0, T) :- {}.\n", atoms.join(", "))
}

/// One `referred` rule whose body binds `n` variables each from the one before, written last
/// first (`B2 = B1 + 1, B1 = B0 + 1, …`), so a pass in source order binds one at a time.
pub fn bindings_program(n: usize) -> String {
    let binds: Vec<String> = (0..n)
        .rev()
        .map(|i| format!("B{} = B{i} + 1", i + 1))
        .collect();
    format!(
        "referred(X, T) :- present(X, T), B0 = 1, {}, B{n} > 0.\n",
        binds.join(", ")
    )
}

/// `n` rules of one atom each, every one an unknown predicate (`h{i}(V, T) :- g{i}(V, T).`): the
/// error path, with a hint looked up for each.
pub fn unknown_program(n: usize) -> String {
    let mut src = String::new();
    for i in 0..n {
        src.push_str(&format!("h{i}(V, T) :- g{i}(V, T).\n"));
    }
    src.push_str("referred(V, T) :- h0(V, T).\n");
    src
}

/// One `referred` rule with a binding of `min` calls nested `n` deep (`Y = min(min(…, 1), 1)`),
/// far past the nesting limit: the parser's error path.
pub fn nested_calls_program(n: usize) -> String {
    format!(
        "referred(X, T) :- present(X, T), Y = {}T{}, Y > 0.\n",
        "min(".repeat(n),
        ", 1)".repeat(n)
    )
}
