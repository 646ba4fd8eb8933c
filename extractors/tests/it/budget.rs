//! [`Budget`] on a real Argoverse 2 log: a pair relation larger than the tuple budget, or not done
//! by its deadline, is an error naming the relation (and is not kept, so a later request with
//! room computes it whole); within the budget the answer is the unlimited one.

use std::time::{Duration, Instant};

use scenalog_extractors::{Budget, ExtractError, Extractor};
use scenalog_facts::read::load_scene;
use scenalog_facts::relation::Request;
use scenalog_testkit::{sample_log, SAMPLE_LOGS};

const LOG: &str = SAMPLE_LOGS[0];

#[test]
fn pair_relations_stop_at_the_budget_and_name_the_relation() {
    let dir = sample_log(LOG);
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

/// The cached list of every pair is kept only within its cap: past it, nothing is kept (the
/// relations visit their pairs per X track instead, in bounded memory) and every pair relation
/// answers exactly as with the cache.
#[test]
fn a_pair_list_past_its_cap_is_not_kept_and_the_answers_are_unchanged() {
    use scenalog_extractors::pairs;
    let dir = sample_log(LOG);
    let scene = load_scene(&dir).unwrap_or_else(|e| panic!("{e}"));
    let cached = Extractor::new(&scene);
    let index = pairs::pair_index(&cached);
    let rows: usize = index
        .all_pairs(cached.kinematics(), usize::MAX)
        .expect("the list fits an unlimited cap")
        .per_x
        .iter()
        .map(|(_, r)| r.len())
        .sum();
    assert!(rows > 1_000, "{rows}");

    let streamed = Extractor::new(&scene);
    let index = pairs::pair_index(&streamed);
    assert!(index.all_pairs(streamed.kinematics(), 1_000).is_none());
    assert!(index.all_pairs_too_large());
    assert!(index.all_pairs_if_built().is_none());
    for name in [
        "near",
        "direction",
        "facing",
        "crossing",
        "following",
        "road_side",
    ] {
        let req = Request::all(name);
        let a = cached.extract_within(&req, &Budget::UNLIMITED).expect(name);
        let b = streamed
            .extract_within(&req, &Budget::UNLIMITED)
            .expect(name);
        assert!(!a.is_empty() || name == "road_side", "{name} is empty");
        assert_eq!(*a, *b, "{name}");
    }
}
