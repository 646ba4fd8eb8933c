//! The long Arrow table holds the same content as the pickle.

use scenalog_eval::{read_any, read_pickle, read_table, write_table};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2/eval")
        .join(name)
}

#[test]
fn feather_equals_pickle_and_round_trips() {
    let dir = tempfile::tempdir().expect("tempdir");
    for stem in ["combined_predictions_dev", "combined_gt_dev"] {
        let from_pkl = read_pickle(&data(&format!("{stem}.pkl"))).expect("pickle");
        let from_arrow = read_table(&data(&format!("{stem}.feather"))).expect("feather");
        assert_eq!(from_arrow, from_pkl, "{stem}");
        let out = dir.path().join(format!("{stem}.feather"));
        write_table(&from_pkl, &out).expect("write");
        assert_eq!(
            read_any(&out).expect("read back"),
            from_pkl,
            "{stem} round trip"
        );
        assert_eq!(
            read_any(&data(&format!("{stem}.pkl"))).expect("any"),
            from_pkl
        );
    }
}

#[test]
fn a_pickle_is_not_an_arrow_table() {
    let e = read_table(&data("combined_gt_dev.pkl"))
        .expect_err("not arrow")
        .to_string();
    assert!(e.contains("combined_gt_dev.pkl"), "{e}");
}
