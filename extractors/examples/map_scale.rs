//! How map indexing grows with the number of lanes: the map's R-trees, lane geometry, lane
//! chains and road sides (`MapIndex::new`) of synthetic maps of 8,000 to 64,000 lanes
//! (`support/grid_map.rs`): `grid` (rows of 1 m lanes, so each lane's chain holds 60 lanes each
//! way), `hub` (every lane leading into one), `tiny` (one row of 1 mm lanes), `overlap` (every
//! lane over the same stretch of road), the median of three builds each.
//!
//! Run: `cargo run --release -p scenalog-extractors --example map_scale [-- SIZES…]` (figures in
//! extractors/README.md).

use std::time::{Duration, Instant};

use scenalog_extractors::map::MapIndex;
use scenalog_facts::Scene;

#[path = "support/grid_map.rs"]
mod grid_map;

/// A map shape: its name and the scene of `n` lanes.
type Shape = (&'static str, fn(usize) -> Scene);

fn main() {
    let sizes: Vec<usize> = {
        let given: Vec<usize> = std::env::args()
            .skip(1)
            .filter_map(|a| a.parse().ok())
            .collect();
        if given.is_empty() {
            vec![8_000, 16_000, 32_000, 64_000]
        } else {
            given
        }
    };
    println!("map | lanes | MapIndex::new (median of 3) | µs per lane");
    let shapes: [Shape; 4] = [
        ("grid", |n| grid_map::grid_scene(n, 1_000, 1.0)),
        ("hub", grid_map::hub_scene),
        ("tiny", grid_map::tiny_lanes_scene),
        ("overlap", grid_map::overlapping_scene),
    ];
    for (shape, make) in shapes {
        for &n in &sizes {
            let scene = make(n);
            let mut times: Vec<Duration> = (0..3)
                .map(|_| {
                    let t = Instant::now();
                    std::hint::black_box(MapIndex::new(&scene.map));
                    t.elapsed()
                })
                .collect();
            times.sort_unstable();
            let t = times[1];
            println!(
                "{shape} | {} | {:.1} ms | {:.2}",
                scene.map.lanes.len(),
                t.as_secs_f64() * 1e3,
                t.as_secs_f64() * 1e6 / scene.map.lanes.len() as f64
            );
        }
    }
}
