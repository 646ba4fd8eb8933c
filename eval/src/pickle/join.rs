//! One submission pickle from parts with disjoint keys (one a log, or one a machine of a
//! distributed run): [`PickleJoin`] writes the parts' sequences one part at a time, in key order,
//! between [`SUBMISSION_HEAD`] and [`SUBMISSION_TAIL`], so the file is byte for byte
//! [`pickle_bytes`](super::write::pickle_bytes) of their union and memory holds one part at a
//! time. A part is added as a submission, or as the bytes [`encode_part`] made of one earlier
//! (a run encodes each log's part as the log finishes, in parallel, and joins the bytes at the
//! end without decoding them again). [`join_pickles`] joins whole pickles given as bytes. All
//! refuse a key in two parts, naming it: the joined submission never holds one sequence twice,
//! or one of two silently.

use std::collections::BTreeSet;
use std::io::{Read, Write};

use super::submission::read_pickle_bytes;
use super::write::{sequences_bytes, SUBMISSION_HEAD, SUBMISSION_TAIL};
use crate::error::EvalError;
use crate::model::{SeqKey, Submission};

/// The keys of a part [`encode_part`] encoded, which [`PickleJoin::add_encoded`] checks before
/// it copies the part's bytes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PartKeys(Vec<SeqKey>);

/// A part's sequences as the bytes [`PickleJoin`] writes for it, and their keys.
pub fn encode_part(part: &Submission) -> (PartKeys, Vec<u8>) {
    (
        PartKeys(part.sequences.keys().cloned().collect()),
        sequences_bytes(part),
    )
}

/// A submission pickle written part by part. Each part's keys must all come after every key of
/// the parts added before it (parts one a log, added in log-id order, do).
pub struct PickleJoin<W: Write> {
    out: W,
    /// What is written, for errors ("`OUT/predictions.pkl`").
    what: String,
    /// The keys written so far (a few per (log, program) pair: small beside the frames).
    written: BTreeSet<SeqKey>,
}

impl<W: Write> PickleJoin<W> {
    /// Starts the pickle in `out`; `what` names it in errors.
    pub fn new(mut out: W, what: &str) -> Result<PickleJoin<W>, EvalError> {
        out.write_all(SUBMISSION_HEAD)
            .map_err(|e| EvalError::Io(what.to_string(), e))?;
        Ok(PickleJoin {
            out,
            what: what.to_string(),
            written: BTreeSet::new(),
        })
    }

    /// Adds a part's sequences. A key already written (the sequence is in two parts), or one
    /// before the greatest key written (the parts are out of key order), is an error naming it.
    pub fn add(&mut self, part: &Submission) -> Result<(), EvalError> {
        self.check(part.sequences.keys())?;
        self.out
            .write_all(&sequences_bytes(part))
            .map_err(|e| EvalError::Io(self.what.clone(), e))?;
        self.written.extend(part.sequences.keys().cloned());
        Ok(())
    }

    /// Adds a part [`encode_part`] encoded: its keys checked as [`PickleJoin::add`] checks them,
    /// then its bytes copied from `bytes` (the file they waited in).
    pub fn add_encoded(&mut self, keys: &PartKeys, bytes: &mut impl Read) -> Result<(), EvalError> {
        self.check(keys.0.iter())?;
        std::io::copy(bytes, &mut self.out).map_err(|e| EvalError::Io(self.what.clone(), e))?;
        self.written.extend(keys.0.iter().cloned());
        Ok(())
    }

    /// Refuses keys already written, and keys (sorted) before the greatest written.
    fn check<'k>(
        &self,
        mut keys: impl Iterator<Item = &'k SeqKey> + Clone,
    ) -> Result<(), EvalError> {
        let refused = |key: &SeqKey, why: &str| {
            EvalError::Format(format!(
                "{}: the sequence ({}, {:?}) {why}",
                self.what, key.0, key.1
            ))
        };
        if let Some(twice) = keys.clone().find(|k| self.written.contains(*k)) {
            return Err(refused(twice, "is in two parts"));
        }
        if let (Some(first), Some(last)) = (keys.next(), self.written.last()) {
            if first < last {
                return Err(refused(
                    first,
                    &format!(
                        "comes before ({}, {:?}) of an earlier part (the parts are not in key \
                         order)",
                        last.0, last.1
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Ends the pickle and hands back the writer (flush or sync it as it needs).
    pub fn finish(mut self) -> Result<W, EvalError> {
        self.out
            .write_all(SUBMISSION_TAIL)
            .map_err(|e| EvalError::Io(self.what.clone(), e))?;
        Ok(self.out)
    }
}

/// One submission pickle from the pickles of disjoint parts (e.g. one a log, from separate runs),
/// each read as the official files are: byte for byte the pickle a single run over all of them
/// writes. The parts may come in any order (they are joined in the order of their first keys);
/// a (log, prompt) key in two parts, or parts whose keys interleave, is an error naming the key.
pub fn join_pickles(parts: &[&[u8]]) -> Result<Vec<u8>, EvalError> {
    let mut read = Vec::with_capacity(parts.len());
    for (i, part) in parts.iter().enumerate() {
        read.push(read_pickle_bytes(part, &format!("part {i}"))?);
    }
    read.sort_by(|a, b| a.sequences.keys().next().cmp(&b.sequences.keys().next()));
    let mut join = PickleJoin::new(Vec::new(), "the joined pickle")?;
    for part in &read {
        join.add(part)?;
    }
    join.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::FrameData;
    use crate::pickle::write::pickle_bytes;

    fn part(keys: &[(&str, &str)]) -> Submission {
        let mut s = Submission::default();
        for (log, prompt) in keys {
            let frame = FrameData {
                timestamp_ns: 1,
                ..FrameData::default()
            };
            s.sequences
                .insert((log.to_string(), prompt.to_string()), vec![frame]);
        }
        s
    }

    #[test]
    fn parts_in_key_order_join_to_the_pickle_of_their_union() {
        let (a, b) = (part(&[("a", "x"), ("a", "y")]), part(&[("b", "x")]));
        let mut union = a.clone();
        union.sequences.extend(b.sequences.clone());
        let mut join = PickleJoin::new(Vec::new(), "t").expect("head");
        join.add(&a).expect("a");
        join.add(&Submission::default()).expect("an empty part");
        join.add(&b).expect("b");
        let joined = join.finish().expect("tail");
        assert_eq!(joined, pickle_bytes(&union));
        // Encoded ahead, the same bytes; an encoded part's keys are checked as a part's are.
        let mut join = PickleJoin::new(Vec::new(), "t").expect("head");
        for p in [&a, &b] {
            let (keys, bytes) = encode_part(p);
            join.add_encoded(&keys, &mut bytes.as_slice())
                .expect("encoded");
        }
        let (keys, bytes) = encode_part(&b);
        let twice = join.add_encoded(&keys, &mut bytes.as_slice());
        assert!(twice.is_err_and(|e| e.to_string().contains("(b, \"x\") is in two parts")));
        assert_eq!(join.finish().expect("tail"), joined);
        // Whole pickles, in any order.
        let (pa, pb) = (pickle_bytes(&a), pickle_bytes(&b));
        assert_eq!(join_pickles(&[&pb, &pa]).expect("join"), joined);
        assert_eq!(
            join_pickles(&[]).expect("nothing"),
            pickle_bytes(&Submission::default())
        );
    }

    #[test]
    fn a_key_in_two_parts_or_out_of_order_is_refused_by_name() {
        let mut join = PickleJoin::new(Vec::new(), "t").expect("head");
        join.add(&part(&[("b", "x")])).expect("b");
        let twice = join
            .add(&part(&[("b", "x"), ("c", "x")]))
            .expect_err("twice");
        assert_eq!(
            twice.to_string(),
            "t: the sequence (b, \"x\") is in two parts"
        );
        let before = join.add(&part(&[("a", "x")])).expect_err("before");
        assert_eq!(
            before.to_string(),
            "t: the sequence (a, \"x\") comes before (b, \"x\") of an earlier part (the parts \
             are not in key order)"
        );
        let (p, q) = (
            pickle_bytes(&part(&[("a", "x"), ("c", "x")])),
            pickle_bytes(&part(&[("b", "x")])),
        );
        let interleaved = join_pickles(&[&p, &q]).expect_err("interleaved");
        assert!(
            interleaved.to_string().contains("not in key order"),
            "{interleaved}"
        );
        let dup = pickle_bytes(&part(&[("a", "x")]));
        let e = join_pickles(&[&dup, &dup]).expect_err("duplicate");
        assert!(e.to_string().contains("(a, \"x\") is in two parts"), "{e}");
    }
}
