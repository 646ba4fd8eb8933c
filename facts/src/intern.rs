//! A small string interner: each distinct string gets a compact [`Sym`], and back.
//!
//! Used by the engine and the extractors to store strings (categories, directions, …) as `u32`s
//! in relation tuples. Symbols are numbered 0, 1, 2, … in the order strings are first interned,
//! so they are stable for one interner and meaningless across interners.

use std::collections::HashMap;
use std::sync::Arc;

/// An interned string: an index into the [`Interner`] that made it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Sym(pub u32);

/// Maps strings to [`Sym`]s and back. Each distinct string is stored once.
#[derive(Debug, Clone, Default)]
pub struct Interner {
    strings: Vec<Arc<str>>,
    index: HashMap<Arc<str>, Sym>,
}

impl Interner {
    /// An empty interner.
    pub fn new() -> Self {
        Self::default()
    }

    /// The symbol of `s`, interning it if it is new.
    ///
    /// # Panics
    /// If more than `u32::MAX` distinct strings are interned.
    pub fn intern(&mut self, s: &str) -> Sym {
        if let Some(&sym) = self.index.get(s) {
            return sym;
        }
        let sym = Sym(u32::try_from(self.strings.len()).expect("more than u32::MAX symbols"));
        let shared: Arc<str> = Arc::from(s);
        self.strings.push(shared.clone());
        self.index.insert(shared, sym);
        sym
    }

    /// The symbol of `s` if it has been interned, without interning it.
    pub fn get(&self, s: &str) -> Option<Sym> {
        self.index.get(s).copied()
    }

    /// The string of a symbol made by this interner.
    ///
    /// # Panics
    /// If `sym` was not made by this interner (use [`Interner::try_resolve`] when unsure).
    pub fn resolve(&self, sym: Sym) -> &str {
        &self.strings[sym.0 as usize]
    }

    /// The string of a symbol, or `None` if this interner never made it.
    pub fn try_resolve(&self, sym: Sym) -> Option<&str> {
        self.strings.get(sym.0 as usize).map(|s| &**s)
    }

    /// The shared string of a symbol (cheap to clone into a relation column), if known.
    pub fn resolve_arc(&self, sym: Sym) -> Option<Arc<str>> {
        self.strings.get(sym.0 as usize).cloned()
    }

    /// Number of distinct strings interned.
    pub fn len(&self) -> usize {
        self.strings.len()
    }

    /// Whether nothing has been interned.
    pub fn is_empty(&self) -> bool {
        self.strings.is_empty()
    }

    /// Every (symbol, string) pair, in symbol order.
    pub fn iter(&self) -> impl Iterator<Item = (Sym, &str)> {
        self.strings
            .iter()
            .enumerate()
            .map(|(i, s)| (Sym(i as u32), &**s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_string_same_symbol_and_round_trip() {
        let mut i = Interner::new();
        let a = i.intern("REGULAR_VEHICLE");
        let b = i.intern("PEDESTRIAN");
        let a2 = i.intern("REGULAR_VEHICLE");
        assert_eq!(a, a2);
        assert_ne!(a, b);
        assert_eq!((a, b), (Sym(0), Sym(1)));
        assert_eq!(i.resolve(a), "REGULAR_VEHICLE");
        assert_eq!(i.resolve(b), "PEDESTRIAN");
        assert_eq!(i.len(), 2);
        assert_eq!(i.get("PEDESTRIAN"), Some(b));
        assert_eq!(i.get("BUS"), None);
        assert_eq!(i.len(), 2, "get does not intern");
        assert_eq!(i.try_resolve(Sym(7)), None);
        assert_eq!(i.resolve_arc(a).as_deref(), Some("REGULAR_VEHICLE"));
        let all: Vec<_> = i.iter().collect();
        assert_eq!(all, vec![(a, "REGULAR_VEHICLE"), (b, "PEDESTRIAN")]);
    }

    #[test]
    fn empty_and_unicode_strings_are_distinct_symbols() {
        let mut i = Interner::new();
        assert!(i.is_empty());
        let e = i.intern("");
        let u = i.intern("vélo");
        assert_ne!(e, u);
        assert_eq!(i.resolve(e), "");
        assert_eq!(i.resolve(u), "vélo");
    }
}
