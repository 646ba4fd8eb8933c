//! Computing the catalog's relations from a Scene. Not built yet (issue: extractors).
