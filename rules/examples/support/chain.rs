//! The generated programs the checker's scale is measured on (`benches/check.rs`,
//! `examples/check_scale.rs`).

/// `n` helper rules, each using the next (so `n` strata), and the `referred` rule.
pub fn chain_program(n: usize) -> String {
    let mut src = String::new();
    for i in 0..n {
        src.push_str(&format!(
            "h{i}(V, T) :- h{}(V, T), speed(V, T, S), S > 0.5.\n",
            i + 1
        ));
    }
    src.push_str(&format!(
        "h{n}(V, T) :- present(V, T).\nreferred(V, T) :- h0(V, T).\n"
    ));
    src
}
