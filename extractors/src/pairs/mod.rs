//! Pairwise relations between objects (built by the pairs work).
