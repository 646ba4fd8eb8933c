//! [`Budget`] on a real Argoverse 2 log: a pair relation larger than the tuple budget, or not done
//! by its deadline, is an error naming the relation (and is not kept, so a later request with
//! room computes it whole); within the budget the answer is the unlimited one.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use scenalog_extractors::{Budget, ExtractError, Extractor};
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::Request;

const LOG: &str = "3b3570b4-7b0b-3268-a571-b0889dbf40b6";

#[test]
fn pair_relations_stop_at_the_budget_and_name_the_relation() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/av2/logs")
        .join(LOG);
    let scene = load_scene(&dir).unwrap_or_else(|e| panic!("{e}"));
    let ex = Extractor::new(&scene);
    let req = Request::all("direction");

    let tight = Budget::new(1_000, Instant::now(), None);
    match ex.extract_within(&req, &tight) {
        Err(ExtractError::TooManyTuples { relation, limit }) => {
            assert_eq!((relation.as_str(), limit), ("direction", 1_000));
        }
        other => panic!("expected the tuple budget to stop `direction`, got {other:?}"),
    }

    let late = Budget::new(usize::MAX, Instant::now(), Some(Duration::ZERO));
    match ex.extract_within(&req, &late) {
        Err(e @ ExtractError::Timeout { .. }) => {
            assert!(e.to_string().contains("`direction`"), "{e}");
        }
        other => panic!("expected the deadline to stop `direction`, got {other:?}"),
    }

    // Nothing of the stopped attempts was kept: with room, the whole relation.
    let whole = ex
        .extract_within(&req, &Budget::UNLIMITED)
        .expect("direction");
    let n = whole.len();
    assert!(n > 1_000, "{n}");
    let exact = Budget::new(n, Instant::now(), Some(Duration::from_secs(600)));
    let fresh = Extractor::new(&scene);
    let within = fresh.extract_within(&req, &exact).expect("fits exactly");
    assert_eq!(*within, *whole);
    // A kept answer larger than a later, smaller budget is refused too.
    assert!(matches!(
        ex.extract_within(&req, &Budget::new(n - 1, Instant::now(), None)),
        Err(ExtractError::TooManyTuples { .. })
    ));
}
