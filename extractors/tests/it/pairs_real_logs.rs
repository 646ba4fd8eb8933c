//! Pair relations on the three real Argoverse 2 logs in `tests/data/av2/logs/`: properties a
//! person can confirm, checked against an independent rectangle distance written here.
//! Run with `--nocapture` to see the per-relation counts.

use std::collections::{BTreeMap, BTreeSet};

use scenalog_extractors::pairs::{self, PairContext, PairIndex};
use scenalog_extractors::query::satisfies;
use scenalog_extractors::Extractor;
use scenalog_extractors::{pair_relation, pair_relations};
use scenalog_facts::relation::{Constraint, RelationData, Request, Value};
use scenalog_facts::{Frame, Scene, TrackId};
use scenalog_testkit::{rows, sample_scenes as scenes};

/// The pair relations' context over the extractor's shared data and `index`.
fn context<'a>(ex: &'a Extractor, index: &'a PairIndex) -> PairContext<'a> {
    PairContext::of(ex, index)
}

/// Answers `req` through the pairs API.
fn answer(ex: &Extractor, req: &Request) -> RelationData {
    let index = pairs::pair_index(ex);
    let ctx = context(ex, &index);
    pair_relation(&ctx, req).unwrap_or_else(|e| panic!("{e}"))
}

fn xyt(row: &[Value]) -> (TrackId, TrackId, Frame) {
    match (&row[0], &row[1], &row[2]) {
        (Value::Track(x), Value::Track(y), Value::Time(t)) => (*x, *y, *t),
        other => panic!("pair rows start with X, Y, T: {other:?}"),
    }
}

// ----- An independent ground-rectangle distance (f64), to check the crate's parry2d one. -----

type P = [f64; 2];

fn corners(scene: &Scene, t: TrackId, f: Frame) -> Option<[P; 4]> {
    let b = scene.track(t).box_at(f)?;
    let c = b.city_center();
    let yaw = b.city_yaw();
    let (s, co) = yaw.sin_cos();
    let (l, w) = (b.size[0] / 2.0, b.size[1] / 2.0);
    let at = |a: f64, b: f64| [c.x + a * co - b * s, c.y + a * s + b * co];
    Some([at(l, w), at(-l, w), at(-l, -w), at(l, -w)])
}

fn separated_on_axes(a: &[P; 4], b: &[P; 4]) -> bool {
    for poly in [a, b] {
        for i in 0..4 {
            let (p, q) = (poly[i], poly[(i + 1) % 4]);
            let axis = [q[1] - p[1], p[0] - q[0]];
            let proj = |r: &[P; 4]| {
                r.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                        let d = v[0] * axis[0] + v[1] * axis[1];
                        (lo.min(d), hi.max(d))
                    })
            };
            let ((alo, ahi), (blo, bhi)) = (proj(a), proj(b));
            if ahi < blo || bhi < alo {
                return true;
            }
        }
    }
    false
}

fn point_segment(p: P, a: P, b: P) -> f64 {
    let (ab, ap) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (ap[0] - t * ab[0]).hypot(ap[1] - t * ab[1])
}

fn rect_distance(a: &[P; 4], b: &[P; 4]) -> f64 {
    if !separated_on_axes(a, b) {
        return 0.0;
    }
    let mut d = f64::INFINITY;
    for (u, v) in [(a, b), (b, a)] {
        for p in u {
            for i in 0..4 {
                d = d.min(point_segment(*p, v[i], v[(i + 1) % 4]));
            }
        }
    }
    d
}

fn distance(scene: &Scene, x: TrackId, y: TrackId, f: Frame) -> f64 {
    match (corners(scene, x, f), corners(scene, y, f)) {
        (Some(a), Some(b)) => rect_distance(&a, &b),
        _ => panic!("a pair at a frame where one box is missing: {x:?} {y:?} {f}"),
    }
}

#[test]
fn near_is_symmetric_exact_and_complete() {
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let near = answer(&ex, &Request::all("near"));
        assert!(!near.is_empty(), "{}: no pairs at all", scene.log_id);
        let mut set: BTreeMap<(TrackId, TrackId, Frame), u64> = BTreeMap::new();
        for r in rows(&near) {
            let (x, y, t) = xyt(&r);
            let Value::Float(d) = r[3] else {
                panic!("D is a float")
            };
            assert_ne!(x, y);
            assert!((0.0..=50.0).contains(&d), "{d}");
            let truth = distance(scene, x, y, t);
            assert!((d - truth).abs() < 1e-3, "{x:?} {y:?} {t}: {d} vs {truth}");
            set.insert((x, y, t), d.to_bits());
        }
        for (&(x, y, t), d) in &set {
            assert_eq!(
                set.get(&(y, x, t)),
                Some(d),
                "near({x:?}, {y:?}, {t}) has no mirror"
            );
        }
        // Complete: every pair clearly within 50 m is there, none clearly beyond (every 10th
        // frame, all pairs by brute force).
        let mut checked = 0;
        for f in (0..scene.num_frames() as Frame).step_by(10) {
            let present: Vec<TrackId> = scene
                .tracks
                .iter()
                .filter(|t| t.box_at(f).is_some())
                .map(|t| t.id)
                .collect();
            for &x in &present {
                for &y in present.iter().filter(|&&y| y != x) {
                    let d = distance(scene, x, y, f);
                    if d < 49.99 {
                        assert!(set.contains_key(&(x, y, f)), "missing {x:?} {y:?} {f}: {d}");
                        checked += 1;
                    } else if d > 50.01 {
                        assert!(!set.contains_key(&(x, y, f)));
                    }
                }
            }
        }
        assert!(checked > 100, "{checked}");
        println!(
            "{}: near {} tuples, {checked} brute-force pairs checked",
            scene.log_id,
            near.len()
        );
    }
}

#[test]
fn no_pair_relation_holds_beyond_fifty_metres() {
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let mut counts = Vec::new();
        for name in pair_relations() {
            let d = answer(&ex, &Request::all(name));
            for r in rows(&d) {
                let (x, y, t) = xyt(&r);
                assert_ne!(x, y, "{name}");
                let dist = distance(scene, x, y, t);
                assert!(dist <= 50.0 + 1e-3, "{name} {x:?} {y:?} {t}: {dist} m");
            }
            counts.push(format!("{name} {}", d.len()));
        }
        println!("{}: {}", scene.log_id, counts.join(", "));
    }
}

/// Rows of the unconstrained relation that satisfy every constraint, in order.
fn filtered(scene: &Scene, full: &RelationData, req: &Request) -> Vec<Vec<Value>> {
    rows(full)
        .into_iter()
        .filter(|r| {
            req.constraints
                .iter()
                .all(|(c, k)| satisfies(scene, &r[*c], k))
        })
        .collect()
}

#[test]
fn pushdown_equals_the_unconstrained_relation_filtered() {
    let cat = |c: &str| Constraint::Category(c.into());
    let s = |v: &str| Constraint::Eq(Value::Str(v.into()));
    let mut nonempty = 0;
    let mut total = 0;
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let ego = Constraint::Eq(Value::Track(scene.ego));
        let mid = (scene.num_frames() / 2) as Frame;
        let cases: Vec<Request> = vec![
            Request {
                name: "near".into(),
                constraints: vec![
                    (0, cat("PEDESTRIAN")),
                    (1, cat("VEHICLE")),
                    (3, Constraint::Lt(5.0)),
                ],
            },
            Request {
                name: "near".into(),
                constraints: vec![(0, ego.clone()), (3, Constraint::Le(10.0))],
            },
            Request {
                name: "near".into(),
                constraints: vec![(2, Constraint::Eq(Value::Time(mid)))],
            },
            Request {
                name: "direction".into(),
                constraints: vec![
                    (0, ego.clone()),
                    (3, s("forward")),
                    (4, Constraint::Lt(20.0)),
                ],
            },
            Request {
                name: "direction".into(),
                constraints: vec![(1, cat("PEDESTRIAN")), (5, Constraint::Lt(1.0))],
            },
            Request {
                name: "facing".into(),
                constraints: vec![(1, cat("VEHICLE")), (2, Constraint::Ge(50.0))],
            },
            Request {
                name: "heading_relative".into(),
                constraints: vec![(0, cat("VEHICLE")), (3, s("opposite"))],
            },
            Request {
                name: "heading_toward".into(),
                constraints: vec![(0, cat("VEHICLE")), (2, Constraint::Lt(100.0))],
            },
            Request {
                name: "crossing".into(),
                constraints: vec![
                    (0, cat("VEHICLE")),
                    (1, cat("PEDESTRIAN")),
                    (3, s("forward")),
                ],
            },
            Request {
                name: "crossing".into(),
                constraints: vec![(3, s("left")), (2, Constraint::Gt(20.0))],
            },
            Request {
                name: "same_lane".into(),
                constraints: vec![(0, ego.clone())],
            },
            Request {
                name: "following".into(),
                constraints: vec![(1, cat("VEHICLE")), (2, Constraint::Le(mid as f64))],
            },
            Request {
                name: "road_side".into(),
                constraints: vec![(0, ego.clone()), (3, s("opposite"))],
            },
        ];
        for req in cases {
            let full = answer(&ex, &Request::all(&req.name));
            let pushed = answer(&ex, &req);
            assert_eq!(
                rows(&pushed),
                filtered(scene, &full, &req),
                "{}: {req:?}",
                scene.log_id
            );
            total += 1;
            nonempty += usize::from(!pushed.is_empty());
        }
    }
    // Most of these select something on real traffic (the checks are not vacuous).
    assert!(nonempty * 3 >= total * 2, "{nonempty} of {total} non-empty");
}

#[test]
fn deterministic_whatever_the_thread_count() {
    let scene = &scenes()[0];
    let run = |threads: usize| -> Vec<RelationData> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        pool.install(|| {
            let ex = Extractor::new(scene);
            pair_relations()
                .into_iter()
                .map(|n| answer(&ex, &Request::all(n)))
                .collect()
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn real_crossings_are_sensible() {
    // Every crossing tuple: Y's centre within the span's 5 m of X's midplane on that side, and the
    // pair appears in `near`. Also print which categories cross which.
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let crossing = answer(&ex, &Request::all("crossing"));
        let near = answer(&ex, &Request::all("near"));
        let near_set: BTreeSet<(TrackId, TrackId, Frame)> =
            rows(&near).iter().map(|r| xyt(r)).collect();
        let mut kinds: BTreeMap<(String, String), usize> = BTreeMap::new();
        for r in rows(&crossing) {
            let (x, y, t) = xyt(&r);
            assert!(near_set.contains(&(x, y, t)));
            let kin = ex.kinematics();
            let (kx, ky) = (&kin.tracks[x.index()], &kin.tracks[y.index()]);
            let (i, j) = (
                kx.index_of(t).expect("x present"),
                ky.index_of(t).expect("y present"),
            );
            let (dx, dy) = (ky.pos[j][0] - kx.pos[i][0], ky.pos[j][1] - kx.pos[i][1]);
            let (s, c) = kx.yaw[i].sin_cos();
            let (fwd, left) = (dx * c + dy * s, -dx * s + dy * c);
            let across = match &r[3] {
                Value::Str(d) if &**d == "forward" || &**d == "backward" => left,
                Value::Str(_) => fwd,
                other => panic!("{other:?}"),
            };
            assert!(across.abs() <= 5.0 + 1e-9, "{r:?}: {across}");
            *kinds
                .entry((
                    scene.track(x).category.clone(),
                    scene.track(y).category.clone(),
                ))
                .or_default() += 1;
        }
        println!(
            "{}: crossing {} tuples {kinds:?}",
            scene.log_id,
            crossing.len()
        );
    }
}

/// Y's raw centre in X's raw box frame at `f`: (forward, left), and X's half length and width.
fn local(scene: &Scene, x: TrackId, y: TrackId, f: Frame) -> ([f64; 2], [f64; 2]) {
    let bx = scene.track(x).box_at(f).expect("x present");
    let by = scene.track(y).box_at(f).expect("y present");
    let (cx, cy) = (bx.city_center(), by.city_center());
    let (s, c) = bx.city_yaw().sin_cos();
    let (dx, dy) = (cy.x - cx.x, cy.y - cx.y);
    (
        [dx * c + dy * s, -dx * s + dy * c],
        [bx.size[0] / 2.0, bx.size[1] / 2.0],
    )
}

#[test]
fn box_relations_agree_with_independent_geometry() {
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let near: BTreeMap<(TrackId, TrackId, Frame), f64> =
            rows(&answer(&ex, &Request::all("near")))
                .iter()
                .map(|r| match r[3] {
                    Value::Float(d) => (xyt(r), d),
                    _ => panic!("D is a float"),
                })
                .collect();
        let direction = answer(&ex, &Request::all("direction"));
        let mut per_dir: BTreeMap<String, usize> = BTreeMap::new();
        for r in rows(&direction) {
            let (x, y, t) = xyt(&r);
            let (Value::Str(dir), Value::Float(dist), Value::Float(lat)) = (&r[3], &r[4], &r[5])
            else {
                panic!("{r:?}")
            };
            assert_eq!(near.get(&(x, y, t)), Some(dist), "Dist is near's D");
            let ([fwd, left], [hl, hw]) = local(scene, x, y, t);
            let (inside, expected_lat) = match &**dir {
                "forward" => (fwd > hl, (left.abs() - hw).max(0.0)),
                "backward" => (fwd < -hl, (left.abs() - hw).max(0.0)),
                "left" => (left > hw, (fwd.abs() - hl).max(0.0)),
                "right" => (left < -hw, (fwd.abs() - hl).max(0.0)),
                other => panic!("{other}"),
            };
            assert!(inside, "{r:?}: {fwd} {left}");
            assert!((lat - expected_lat).abs() < 1e-6, "{r:?}: {expected_lat}");
            *per_dir.entry(dir.to_string()).or_default() += 1;
        }
        // Every near pair whose Y centre lies outside X's box has at least one direction.
        let dir_pairs: BTreeSet<(TrackId, TrackId, Frame)> =
            rows(&direction).iter().map(|r| xyt(r)).collect();
        for &(x, y, t) in near.keys() {
            let ([fwd, left], [hl, hw]) = local(scene, x, y, t);
            if fwd.abs() > hl + 1e-6 || left.abs() > hw + 1e-6 {
                assert!(dir_pairs.contains(&(x, y, t)), "{x:?} {y:?} {t}");
            }
        }
        let facing = answer(&ex, &Request::all("facing"));
        for r in rows(&facing) {
            let (x, y, t) = xyt(&r);
            let ([fwd, left], _) = local(scene, x, y, t);
            assert!(left.atan2(fwd).to_degrees().abs() <= 22.5 + 1e-9, "{r:?}");
        }
        // Following: the lead's centre is ahead of X's front by less than 25 m, within 5 m to the
        // side (raw centres here, smoothed in the relation: 1 m of slack), both in lanes.
        let in_lane: BTreeSet<(TrackId, Frame)> = {
            let d = ex
                .extract(&Request::all("in_lane"))
                .unwrap_or_else(|e| panic!("{e}"));
            rows(&d)
                .iter()
                .map(|r| match (&r[0], &r[1]) {
                    (Value::Track(x), Value::Time(t)) => (*x, *t),
                    other => panic!("{other:?}"),
                })
                .collect()
        };
        let following = answer(&ex, &Request::all("following"));
        for r in rows(&following) {
            let (x, y, t) = xyt(&r);
            let ([fwd, left], [hl, _]) = local(scene, x, y, t);
            assert!(
                fwd - hl > -1.0 && fwd - hl < 26.0 && left.abs() < 6.0,
                "{r:?}"
            );
            assert!(
                in_lane.contains(&(x, t)) && in_lane.contains(&(y, t)),
                "{r:?}"
            );
        }
        for name in ["same_lane", "road_side"] {
            for r in rows(&answer(&ex, &Request::all(name))) {
                let (x, y, t) = xyt(&r);
                assert!(
                    in_lane.contains(&(x, t)) && in_lane.contains(&(y, t)),
                    "{name} {r:?}"
                );
            }
        }
        println!(
            "{}: direction {per_dir:?}, facing {}, following {}",
            scene.log_id,
            facing.len(),
            following.len()
        );
    }
}

/// On the real logs, `crossing_detail` bounded to `crossing`'s extents (`Reach <= 10`,
/// `Off <= 5`) contains every `crossing` tuple; the extra tuples are only those of events whose
/// first sample past the plane is already more than 5 m from it (documented), so they are few.
#[test]
fn crossing_detail_bounded_to_ten_and_five_contains_crossing() {
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let fixed: BTreeSet<String> = rows(&answer(&ex, &Request::all("crossing")))
            .iter()
            .map(|r| format!("{:?}", &r[..4]))
            .collect();
        let detail = answer(&ex, &Request::all("crossing_detail"));
        let bounded: BTreeSet<String> = rows(&detail)
            .iter()
            .filter(|r| {
                matches!((&r[5], &r[6]), (Value::Float(reach), Value::Float(off)) if *reach <= 10.0 && *off <= 5.0)
            })
            .map(|r| format!("{:?}", &r[..4]))
            .collect();
        let missing: Vec<&String> = fixed.difference(&bounded).collect();
        assert!(missing.is_empty(), "{}: {missing:?}", scene.log_id);
        let extra = bounded.len() - fixed.len();
        println!(
            "{}: crossing {} tuples, crossing_detail {} ({} within 10 m / 5 m, {extra} more than crossing)",
            scene.log_id,
            fixed.len(),
            detail.len(),
            bounded.len()
        );
        assert!(
            extra * 10 <= fixed.len().max(10),
            "{}: {extra} extra of {}",
            scene.log_id,
            fixed.len()
        );
    }
}

/// The sorted, distinct (X, Y, T) triples of `rows`.
fn triples_of<'a>(rows: impl Iterator<Item = &'a Vec<Value>>) -> Vec<(TrackId, TrackId, Frame)> {
    let set: BTreeSet<(TrackId, TrackId, Frame)> = rows.map(|r| xyt(r)).collect();
    set.into_iter().collect()
}

#[test]
fn a_tuple_level_demand_gives_exactly_the_demanded_tuples() {
    // Every pair relation on every real log: asked with `Triples` (every third (X, Y, T) of the
    // whole relation, the same pairs at frames they do not hold at, and the pairs turned around),
    // the answer is the whole relation's rows at those triples, no more and no fewer.
    let mut demanded_rows = 0;
    for scene in scenes() {
        let ex = Extractor::new(scene);
        for name in pair_relations() {
            let full = rows(&answer(&ex, &Request::all(name)));
            let some = triples_of(full.iter().step_by(3));
            let mut ts: BTreeSet<(TrackId, TrackId, Frame)> = some.iter().copied().collect();
            for &(x, y, t) in some.iter().step_by(5) {
                ts.insert((y, x, t));
                ts.insert((x, y, t + 7));
                ts.insert((x, y, t.saturating_sub(13)));
            }
            let ts: Vec<(TrackId, TrackId, Frame)> = ts.into_iter().collect();
            let want: Vec<Vec<Value>> = full
                .iter()
                .filter(|r| ts.binary_search(&xyt(r)).is_ok())
                .cloned()
                .collect();
            let req = Request {
                name: name.to_string(),
                constraints: vec![(0, Constraint::Triples(ts.into()))],
            };
            let got = rows(&answer(&ex, &req));
            assert_eq!(got.len(), want.len(), "{}: {name}", scene.log_id);
            assert!(got == want, "{}: {name} differs", scene.log_id);
            demanded_rows += got.len();
            // The same through the extractor's cache (a `Triples` answer is not kept), with a
            // fixed string too where the relation has one.
            if name == "heading_relative" {
                let same = Constraint::Eq(Value::Str("same".into()));
                let ts = triples_of(full.iter().step_by(2));
                let req = Request {
                    name: name.to_string(),
                    constraints: vec![(3, same.clone()), (0, Constraint::Triples(ts.into()))],
                };
                let got = ex.extract(&req).unwrap_or_else(|e| panic!("{e}"));
                assert_eq!(rows(&got), filtered_triples(scene, &full, &req));
            }
        }
        // An empty demand needs nothing.
        let req = Request {
            name: "near".into(),
            constraints: vec![(0, Constraint::Triples(Vec::new().into()))],
        };
        assert!(answer(&ex, &req).is_empty());
    }
    assert!(demanded_rows > 10_000, "{demanded_rows}");
}

/// `full`'s rows that satisfy `req`'s constraints, `Triples` on (X, Y, T) included.
fn filtered_triples(scene: &Scene, full: &[Vec<Value>], req: &Request) -> Vec<Vec<Value>> {
    full.iter()
        .filter(|r| {
            req.constraints.iter().all(|(c, k)| match k {
                Constraint::Triples(ts) => ts.binary_search(&xyt(r)).is_ok(),
                _ => satisfies(scene, &r[*c], k),
            })
        })
        .cloned()
        .collect()
}

#[test]
fn a_malformed_tuple_level_demand_is_an_error() {
    let scene = &scenes()[0];
    let ex = Extractor::new(scene);
    let (a, b) = (TrackId(0), TrackId(1));
    for (name, col, ts) in [
        // Unsorted triples.
        ("near", 0, vec![(b, a, 3), (a, b, 3)]),
        // Not on (track, track, time) columns.
        ("near", 1, vec![(a, b, 3)]),
        ("speed", 0, vec![(a, b, 3)]),
    ] {
        let req = Request {
            name: name.into(),
            constraints: vec![(col, Constraint::Triples(ts.into()))],
        };
        assert!(ex.extract(&req).is_err(), "{name} {col}");
    }
}

#[test]
fn following_is_near_filtered_by_follows() {
    // `following` looks for leads only in the part of X's surroundings a lead can be in (ahead of
    // X), not in the whole 50 m radius: it must still find exactly the pairs within 50 m that
    // `follows` accepts, here enumerated from `near` (checked above against brute force).
    let mut total = 0;
    for scene in scenes() {
        let ex = Extractor::new(scene);
        let index = pairs::pair_index(&ex);
        let ctx = context(&ex, &index);
        let near = rows(&answer(&ex, &Request::all("near")));
        let want: Vec<(TrackId, TrackId, Frame)> = triples_of(near.iter().filter(|r| {
            let (x, y, t) = xyt(r);
            let Some(fb) = index.frame(ctx.kin, t) else {
                return false;
            };
            match (fb.of(x), fb.of(y)) {
                (Some(bx), Some(by)) => pairs::lanes::follows(&ctx, bx, by),
                _ => false,
            }
        }));
        let got = triples_of(rows(&answer(&ex, &Request::all("following"))).iter());
        assert_eq!(got, want, "{}", scene.log_id);
        total += got.len();
    }
    assert!(total > 1000, "{total}");
}
