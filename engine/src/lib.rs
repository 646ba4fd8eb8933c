//! Evaluating checked Scenalog programs with datafrog. Not built yet (issue: engine).
