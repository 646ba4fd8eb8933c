//! Synthesizing Scenalog programs from descriptions with an LLM. Not built yet (issue: synth).
