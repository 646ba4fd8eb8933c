//! Pickle round trips and bad-input errors on the real fixture.

use scenalog_eval::{
    evaluate, pickle_bytes, read_pickle, read_pickle_bytes, write_pickle, EvalOptions,
};
use std::path::PathBuf;
use std::process::Command;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2/eval")
        .join(name)
}

#[test]
fn written_pickle_reads_back_identically() {
    for file in ["combined_predictions_dev.pkl", "combined_gt_dev.pkl"] {
        let sub = read_pickle(&data(file)).expect("read");
        let bytes = pickle_bytes(&sub);
        let back = read_pickle_bytes(&bytes, "written").expect("read back");
        assert_eq!(back, sub, "{file}");
    }
}

fn numpy_python() -> bool {
    Command::new("python3")
        .args(["-c", "import numpy"])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Python's `pickle.load` reads what we write and finds the same structure (keys, types, dtypes, values)
/// as in the official file. Skipped (with a note) when python3 with numpy is not available.
#[test]
fn python_loads_written_pickle_with_the_same_structure() {
    if !numpy_python() {
        eprintln!("note: python3 with numpy not available; skipping the Python round trip");
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    for file in ["combined_predictions_dev.pkl", "combined_gt_dev.pkl"] {
        let sub = read_pickle(&data(file)).expect("read");
        let out = dir.path().join(file);
        write_pickle(&sub, &out).expect("write");
        let script = r#"
import pickle, sys, warnings
import numpy as np
warnings.simplefilter("ignore")
a = pickle.load(open(sys.argv[1], "rb"))
b = pickle.load(open(sys.argv[2], "rb"))
assert list(a.keys()) == list(b.keys()) or sorted(a.keys()) == sorted(b.keys()), "keys"
for k in a:
    fa, fb = a[k], b[k]
    assert len(fa) == len(fb), (k, "frames")
    for x, y in zip(fa, fb):
        assert set(x.keys()) == set(y.keys()), (k, set(x.keys()) ^ set(y.keys()))
        for f in x:
            u, v = x[f], y[f]
            assert type(u) == type(v), (k, f, type(u), type(v))
            if isinstance(u, np.ndarray):
                assert u.dtype == v.dtype and u.shape == v.shape, (k, f, u.dtype, v.dtype, u.shape, v.shape)
                assert np.array_equal(u, v), (k, f)
            elif isinstance(u, list):
                assert [type(t) for t in u] == [type(t) for t in v] and u == v, (k, f)
            else:
                assert u == v, (k, f, repr(u), repr(v))
print("ok")
"#;
        let o = Command::new("python3")
            .args(["-c", script])
            .arg(data(file))
            .arg(&out)
            .output()
            .expect("python3");
        assert!(
            o.status.success(),
            "{file}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert_eq!(String::from_utf8_lossy(&o.stdout).trim(), "ok");
    }
}

#[test]
fn truncated_and_foreign_pickles_are_errors() {
    let bytes = std::fs::read(data("combined_gt_dev.pkl")).expect("read");
    for cut in [0, 1, 2, 11, 100, 5000, bytes.len() / 2, bytes.len() - 1] {
        let e = read_pickle_bytes(&bytes[..cut], "cut").expect_err("truncated must fail");
        assert!(e.to_string().contains("cut"), "{e}");
    }
    let feather = std::fs::read(data("combined_gt_dev.feather")).expect("read");
    let e = read_pickle_bytes(&feather, "feather").expect_err("foreign");
    assert!(e.to_string().contains("unknown opcode 0x41"), "{e}");
    // What is refused says why and what to write instead; nothing is executed.
    for (bytes, says) in [
        (
            &b"\x80\x02cos\nsystem\n(X\x02\x00\x00\x00lstR."[..],
            "global os.system",
        ),
        (
            &b"\x80\x02cpandas.core.frame\nDataFrame\n)R."[..],
            "store plain numpy arrays",
        ),
        (&b"\x80\x05\x97."[..], "without `buffer_callback`"),
        (&b"\x80\x06N."[..], "protocol=5"),
        (&b"(i__main__\nC\n."[..], "nothing is executed"),
    ] {
        let e = read_pickle_bytes(bytes, "refused").expect_err("refused");
        assert!(e.to_string().contains(says), "{e}");
    }
    // every single-byte corruption of the header region errors or parses, never panics
    for i in 0..400 {
        let mut b = bytes.clone();
        b[i] ^= 0x5a;
        let _ = read_pickle_bytes(&b, "corrupt");
    }
}

#[test]
fn inconsistent_submissions_name_the_place() {
    let gt = read_pickle(&data("combined_gt_dev.pkl")).expect("read");
    let pred = read_pickle(&data("combined_predictions_dev.pkl")).expect("read");
    let opts = EvalOptions::default();
    let key = (
        "3bffdcff-c3a7-38b6-a0f2-64196d130958".to_string(),
        "stopped car".to_string(),
    );

    let mut p = pred.clone();
    p.sequences.remove(&key);
    let e = evaluate(&p, &gt, &opts)
        .expect_err("missing sequence")
        .to_string();
    assert!(
        e.contains("stopped car") && e.contains("not in the predictions"),
        "{e}"
    );

    let mut g = gt.clone();
    g.sequences.remove(&key);
    let e = evaluate(&pred, &g, &opts)
        .expect_err("extra sequence")
        .to_string();
    assert!(e.contains("not in the ground truth"), "{e}");

    let mut p = pred.clone();
    p.sequences.get_mut(&key).unwrap()[3].score = None;
    let e = evaluate(&p, &gt, &opts)
        .expect_err("missing score")
        .to_string();
    assert!(e.contains("frame 3") && e.contains("score"), "{e}");

    let mut p = pred.clone();
    p.sequences.get_mut(&key).unwrap().swap(4, 5);
    let e = evaluate(&p, &gt, &opts)
        .expect_err("out of order")
        .to_string();
    assert!(e.contains("frame 5") && e.contains("timestamp_ns"), "{e}");

    // a frame built in code with mismatched arrays is an error, not a panic
    let mut p = pred.clone();
    p.sequences.get_mut(&key).unwrap()[2].track_id.pop();
    let e = evaluate(&p, &gt, &opts)
        .expect_err("mismatched")
        .to_string();
    assert!(e.contains("frame 2") && e.contains("track_id"), "{e}");

    // mismatched array lengths in a pickle: shorten one frame's yaw and write it out
    let mut p = pred.clone();
    p.sequences.get_mut(&key).unwrap()[7].yaw.pop();
    let e = read_pickle_bytes(&pickle_bytes(&p), "bad.pkl")
        .expect_err("mismatched lengths")
        .to_string();
    assert!(
        e.contains("stopped car") && e.contains("frame 7") && e.contains("yaw"),
        "{e}"
    );
}

/// A frame of `n` objects as a Python value (the fields the reader checks).
fn frame_value(n: usize) -> scenalog_eval::PyValue {
    use scenalog_eval::PyValue as P;
    let s = |x: &str| P::Str(x.to_string());
    P::Dict(vec![
        (s("timestamp_ns"), P::I64(315_969_904_359_876_000)),
        (
            s("translation_m"),
            P::F64Array(vec![n, 3], vec![1.5; n * 3]),
        ),
        (s("size"), P::F32Array(vec![n, 3], vec![2.0; n * 3])),
        (s("yaw"), P::F32Array(vec![n], vec![0.1; n])),
        (s("label"), P::I64Array(vec![0; n])),
        (s("name"), P::StrArray(vec!["REFERRED_OBJECT".into(); n])),
        (s("track_id"), P::I64Array((0..n as i64).collect())),
        (s("score"), P::F32Array(vec![n], vec![0.5; n])),
    ])
}

/// A pickle `{("log", "prompt"): [frame, frame, …]}` whose frames are one frame dict repeated by
/// reference (MEMOIZE once, then BINGET), as a memo bomb is built.
fn memo_bomb(n: usize, repeats: usize) -> Vec<u8> {
    let frame = scenalog_eval::encode_value(&frame_value(n));
    let body = &frame[2..frame.len() - 1];
    let mut out = vec![0x80, 4, b'}', b'('];
    for s in ["log", "prompt"] {
        out.push(b'X');
        out.extend_from_slice(&(s.len() as u32).to_le_bytes());
        out.extend_from_slice(s.as_bytes());
    }
    out.extend_from_slice(&[0x86, b']', b'(']);
    out.extend_from_slice(body);
    out.push(0x94);
    for _ in 1..repeats {
        out.extend_from_slice(&[b'h', 0]);
    }
    out.extend_from_slice(b"eu.");
    out
}

#[test]
fn a_frame_repeated_by_reference_reads_when_small() {
    let sub = read_pickle_bytes(&memo_bomb(10, 50), "small").expect("a few shared frames read");
    let frames = &sub.sequences[&("log".to_string(), "prompt".to_string())];
    assert_eq!(frames.len(), 50);
    assert!(frames.iter().all(|f| f.translation_m.len() == 10));
}

/// A 2.6 MB pickle that repeats a 20,000-object frame 100,000 times by reference would decode to
/// about 100 GB: it is an error naming the cause, found after a bounded amount of decoding.
#[test]
fn a_memo_bomb_is_an_error_not_unbounded_memory() {
    let bytes = memo_bomb(20_000, 100_000);
    assert!(bytes.len() < 3_000_000, "{}", bytes.len());
    let e = read_pickle_bytes(&bytes, "bomb.pkl").expect_err("a memo bomb must not decode");
    let msg = e.to_string();
    assert!(msg.contains("bomb.pkl"), "{msg}");
    assert!(msg.contains("times the file's size"), "{msg}");
}

/// A top level other than a dict is said at the opcode that makes it, before the rest of the
/// file is decoded: each of these is followed by bytes no pickle holds (opcode 0xff), so an
/// error naming the top level proves the reader stopped there. A dict made every way Python
/// writes one (empty then filled, `(dp0`, MARK items DICT, OrderedDict) still reads.
#[test]
fn the_wrong_top_level_is_said_before_the_rest_is_read() {
    let rest = [0xffu8; 64];
    for (head, kind) in [
        (
            &b"\x80\x04\x95\x00\x00\x00\x00\x00\x00\x00\x00]\x94("[..],
            "a list",
        ),
        (&b"(lp0\n"[..], "a list"),
        (&b"\x80\x02)"[..], "a tuple"),
        (&b"\x80\x02K\x01"[..], "an int"),
        (&b"\x80\x02N"[..], "a None"),
    ] {
        let bytes = [head, &rest[..]].concat();
        let e = read_pickle_bytes(&bytes, "wrong.pkl").expect_err("not a dict");
        let msg = e.to_string();
        assert!(
            msg.contains(&format!(
                "the top level is not a dict: it starts with {kind}"
            )),
            "{msg}"
        );
        assert!(!msg.contains("0xff"), "decoded past the top level: {msg}");
    }
    let seq = b"X\x03\x00\x00\x00logX\x06\x00\x00\x00prompt\x86]";
    for dict in [
        [&b"\x80\x02}q\x00("[..], seq, b"u."].concat(),
        [&b"(dp0\n("[..], seq, b"u."].concat(),
        [&b"\x80\x02("[..], seq, b"d."].concat(),
        [&b"\x80\x02ccollections\nOrderedDict\n)R("[..], seq, b"u."].concat(),
    ] {
        let sub = read_pickle_bytes(&dict, "dict.pkl").expect("a dict top level reads");
        assert_eq!(sub.sequences.len(), 1);
    }
}

/// The file check refuses from its first bytes a pickle whose top level is another type, and
/// lets a dict (any protocol), an Arrow table and a head too short to judge through.
#[test]
fn the_file_check_judges_the_top_level_from_the_head() {
    use scenalog_eval::{dict_pickle_ends, submission_ends};
    let e = dict_pickle_ends(
        b"\x80\x04\x95\x10\x00\x00\x00\x00\x00\x00\x00]\x94(K\x01K\x02",
        b"e.",
    )
    .expect_err("a list");
    assert!(
        e.contains("the top level is not a dict: it starts with a list"),
        "{e}"
    );
    for head in [
        &b"\x80\x04\x95\x10\x00\x00\x00\x00\x00\x00\x00}\x94("[..],
        b"(dp0\n",
        b"\x80",
        b"(",
    ] {
        assert!(dict_pickle_ends(head, b"s.").is_ok(), "{head:?}");
    }
    assert!(dict_pickle_ends(b"}", b"s").is_err(), "no STOP");
    assert!(submission_ends(b"ARROW1\x00\x00", b"ARROW1").is_ok());
    assert!(submission_ends(b"ARROW1", b".").is_err());
    assert!(submission_ends(b"\x80\x02]", b".").is_err());
    let bytes = std::fs::read(data("combined_gt_dev.pkl")).expect("read");
    assert!(dict_pickle_ends(&bytes[..64], &bytes[bytes.len() - 64..]).is_ok());
}

/// Wrong top levels as Python's `pickle.dumps` writes them, in every protocol (0-5): a list of
/// ten thousand ints, a tuple, a string, None. Each is refused naming the top level, before the
/// rest is decoded, by the reader and, for the list, already by the file check of its first 64
/// bytes. Skipped (with a note) when python3 is not available.
#[test]
fn python_pickles_of_another_top_level_are_refused_early_in_every_protocol() {
    let script = "import pickle, sys\n\
        for p in range(6):\n\
        \x20   for obj in (list(range(10000)), ('a', 'b'), 'x', None):\n\
        \x20       b = pickle.dumps(obj, protocol=p)\n\
        \x20       sys.stdout.write(b.hex() + '\\n')\n";
    let Ok(out) = Command::new("python3").args(["-c", script]).output() else {
        eprintln!("note: python3 not available; skipped");
        return;
    };
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).expect("hex");
    let pickles: Vec<Vec<u8>> = text
        .lines()
        .map(|l| {
            (0..l.len())
                .step_by(2)
                .map(|i| u8::from_str_radix(&l[i..i + 2], 16).expect("hex"))
                .collect()
        })
        .collect();
    assert_eq!(pickles.len(), 24);
    for (i, bytes) in pickles.iter().enumerate() {
        // From protocol 2 a small tuple's items come first, then TUPLE2 packs them.
        let tuple = if i / 4 < 2 { "a tuple" } else { "a str" };
        let (protocol, kind) = (i / 4, ["a list", tuple, "a str", "a None"][i % 4]);
        let e = read_pickle_bytes(bytes, "python.pkl").expect_err("not a dict");
        assert!(
            e.to_string().contains(&format!(
                "the top level is not a dict: it starts with {kind}"
            )),
            "protocol {protocol}: {e}"
        );
        if i % 4 == 0 {
            let head = &bytes[..64.min(bytes.len())];
            let tail = &bytes[bytes.len() - 64..];
            let e = scenalog_eval::dict_pickle_ends(head, tail).expect_err("refused from the head");
            assert!(
                e.contains("the top level is not a dict: it starts with a list"),
                "protocol {protocol}: {e}"
            );
        }
    }
}
