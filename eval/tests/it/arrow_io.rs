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

/// Our tables are zstd-compressed with `log_id`, `prompt` and `name` dictionary-encoded; they
/// read back to the same submission, and so does an uncompressed or LZ4 one; a value missing
/// from given dictionaries is an error naming it.
#[test]
fn compressed_dictionary_tables_round_trip() {
    use scenalog_eval::arrow_table::{table_bytes, TableDictionaries, TABLE_COMPRESSION};
    use scenalog_eval::table_from_bytes;
    let gt = read_pickle(&data("combined_gt_dev.pkl")).expect("pickle");
    let dicts = TableDictionaries::of(&gt);
    assert_eq!(dicts.log_ids.len(), 2);
    let plain = table_bytes(&gt, &dicts, None).expect("plain");
    let zstd = table_bytes(&gt, &dicts, Some(TABLE_COMPRESSION)).expect("zstd");
    let lz4 = table_bytes(&gt, &dicts, Some(arrow_ipc::CompressionType::LZ4_FRAME)).expect("lz4");
    assert!(
        zstd.len() * 3 < plain.len(),
        "{} vs {}",
        zstd.len(),
        plain.len()
    );
    for (bytes, what) in [(&plain, "plain"), (&zstd, "zstd"), (&lz4, "lz4")] {
        assert_eq!(table_from_bytes(bytes, what).expect(what), gt, "{what}");
    }
    let schema = scenalog_input::read_schema(&zstd).expect("schema");
    for column in ["log_id", "prompt", "name"] {
        let ty = schema.field_with_name(column).expect(column).data_type();
        assert!(
            matches!(ty, arrow_schema::DataType::Dictionary(..)),
            "{column}: {ty:?}"
        );
    }
    // Wider dictionaries than the values (a run's, shared by its logs) are fine; narrower not.
    let mut wide = dicts.clone();
    wide.log_ids
        .push("ffffffff-0000-0000-0000-000000000000".into());
    wide.normalise();
    let bytes = table_bytes(&gt, &wide, Some(TABLE_COMPRESSION)).expect("wide");
    assert_eq!(table_from_bytes(&bytes, "wide").expect("wide"), gt);
    let mut narrow = dicts.clone();
    let gone = narrow.prompts.pop().expect("a prompt");
    let e = table_bytes(&gt, &narrow, None)
        .expect_err("narrow")
        .to_string();
    assert!(e.contains("prompt") && e.contains(&gone), "{e}");
}
