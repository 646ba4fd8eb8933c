//! Kinematics of every track: smoothed city-frame positions and their derivatives, per box.
//!
//! The types here are the contract between kinematics, events, map and pair extraction.

use scenalog_facts::{Frame, Scene, Track};

use crate::thresholds::{MEDIAN_WINDOW, STATIONARY_MAX_DIAGONAL_M};

/// Kinematics of one track, one entry per box of the track (same order as `Track::boxes`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrackKinematics {
    /// Frame of each entry.
    pub frames: Vec<Frame>,
    /// Seconds from the log's start of each entry.
    pub times: Vec<f64>,
    /// Raw city-frame box centre (x, y), metres.
    pub center: Vec<[f64; 2]>,
    /// Smoothed city-frame position (x, y), metres.
    pub pos: Vec<[f64; 2]>,
    /// Smoothed city-frame velocity (vx, vy), m/s.
    pub vel: Vec<[f64; 2]>,
    /// Speed, m/s (norm of `vel`).
    pub speed: Vec<f64>,
    /// Forward acceleration in the object's own frame, m/s².
    pub accel: Vec<f64>,
    /// Lateral acceleration in the object's own frame (+ left), m/s².
    pub lat_accel: Vec<f64>,
    /// Box heading (yaw) in the city frame, radians.
    pub yaw: Vec<f64>,
    /// Yaw rate, deg/s (+ counter-clockwise), unsmoothed.
    pub yaw_rate: Vec<f64>,
    /// Whether the whole track is stationary (smoothed positions' bounding-box diagonal < 3 m).
    pub stationary: bool,
    /// The median filters' window in samples ([`median_window`]).
    pub window: usize,
}

impl TrackKinematics {
    /// Index of the entry at `frame`, if the track is annotated there.
    pub fn index_of(&self, frame: Frame) -> Option<usize> {
        self.frames.binary_search(&frame).ok()
    }
}

/// Kinematics of every track of a scene, indexed by `TrackId::index()`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Kinematics {
    /// One entry per track of the scene.
    pub tracks: Vec<TrackKinematics>,
}

/// Computes the kinematics of every track (in parallel over tracks; the result does not depend on
/// the thread count).
pub fn compute(scene: &Scene) -> Kinematics {
    use rayon::prelude::*;
    let tracks = scene
        .tracks
        .par_iter()
        .map(|t| track_kinematics(scene, t))
        .collect();
    Kinematics { tracks }
}

/// Computes the kinematics of one track of `scene`.
pub fn track_kinematics(scene: &Scene, track: &Track) -> TrackKinematics {
    let n = track.boxes.len();
    let frames: Vec<Frame> = track.boxes.iter().map(|b| b.frame).collect();
    // Seconds of each box; a frame outside the timeline (cannot happen for a loaded scene) falls
    // back to 10 Hz so nothing divides by zero.
    let times: Vec<f64> = frames
        .iter()
        .map(|&f| scene.timeline.seconds(f).unwrap_or(f as f64 * 0.1))
        .collect();
    let center: Vec<[f64; 2]> = track
        .boxes
        .iter()
        .map(|b| {
            let c = b.city_center();
            [c.x, c.y]
        })
        .collect();
    let yaw: Vec<f64> = track.boxes.iter().map(|b| b.city_yaw()).collect();

    let window = median_window(&times);
    let pos = median_filter_2d(&center, window);
    let vel = median_filter_2d(&derivative_2d(&pos, &times), window);
    let acc = median_filter_2d(&derivative_2d(&vel, &times), window);
    let speed: Vec<f64> = vel.iter().map(|v| v[0].hypot(v[1])).collect();
    let mut accel = Vec::with_capacity(n);
    let mut lat_accel = Vec::with_capacity(n);
    for (a, &h) in acc.iter().zip(&yaw) {
        let (s, c) = h.sin_cos();
        accel.push(a[0] * c + a[1] * s);
        lat_accel.push(-a[0] * s + a[1] * c);
    }
    let yaw_rate = yaw_rate_deg_s(&yaw, &times);
    let stationary = bbox_diagonal(&pos) < STATIONARY_MAX_DIAGONAL_M;
    TrackKinematics {
        frames,
        times,
        center,
        pos,
        vel,
        speed,
        accel,
        lat_accel,
        yaw,
        yaw_rate,
        stationary,
        window,
    }
}

/// The median filters' window in samples for a track sampled at `times` (seconds): the same
/// span of time as [`MEDIAN_WINDOW`] frames of 0.1 s at the track's median spacing, odd, at
/// least 1 and at most [`MEDIAN_WINDOW`]: 7 samples at 10 Hz, 1 at 2 Hz (a 7-sample window there
/// would smooth over 3.5 s).
pub fn median_window(times: &[f64]) -> usize {
    let mut gaps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    if gaps.is_empty() {
        return MEDIAN_WINDOW;
    }
    gaps.sort_by(f64::total_cmp);
    let gap = gaps[gaps.len() / 2];
    if gap <= 0.0 || !gap.is_finite() {
        return MEDIAN_WINDOW;
    }
    let w = ((MEDIAN_WINDOW as f64 * 0.1) / gap).round() as usize;
    let w = w.clamp(1, MEDIAN_WINDOW);
    w - (1 - (w & 1))
}

/// The window actually used for `n` samples: `window`, or the largest odd number `<= n`.
fn effective_window(n: usize, window: usize) -> usize {
    let w = window.min(n).max(1);
    // Round down to odd.
    w - (1 - (w & 1))
}

/// Median filter of one series. The window is centred; near the ends it shrinks symmetrically to
/// the boxes that exist on both sides (so the first and last values pass unchanged and a steady
/// motion is never bent at the ends, unlike zero padding or a one-sided window).
pub fn median_filter(x: &[f64], window: usize) -> Vec<f64> {
    let n = x.len();
    let half = effective_window(n, window) / 2;
    let mut buf = Vec::with_capacity(2 * half + 1);
    (0..n)
        .map(|i| {
            let h = half.min(i).min(n - 1 - i);
            buf.clear();
            buf.extend_from_slice(&x[i - h..=i + h]);
            median(&mut buf)
        })
        .collect()
}

/// Median of a buffer (mean of the two middle values for an even count); 0 when empty.
fn median(buf: &mut [f64]) -> f64 {
    if buf.is_empty() {
        return 0.0;
    }
    // Insertion sort: the windows are a handful of values.
    for i in 1..buf.len() {
        let mut j = i;
        while j > 0 && buf[j - 1].total_cmp(&buf[j]).is_gt() {
            buf.swap(j - 1, j);
            j -= 1;
        }
    }
    let m = buf.len() / 2;
    if buf.len() & 1 == 1 {
        buf[m]
    } else {
        0.5 * (buf[m - 1] + buf[m])
    }
}

fn median_filter_2d(x: &[[f64; 2]], window: usize) -> Vec<[f64; 2]> {
    let xs: Vec<f64> = x.iter().map(|p| p[0]).collect();
    let ys: Vec<f64> = x.iter().map(|p| p[1]).collect();
    let fx = median_filter(&xs, window);
    let fy = median_filter(&ys, window);
    fx.into_iter().zip(fy).map(|(a, b)| [a, b]).collect()
}

/// Indices of the neighbours used for the derivative at `i`: ±1, one-sided at the ends.
fn diff_span(i: usize, n: usize) -> (usize, usize) {
    (i.saturating_sub(1), (i + 1).min(n - 1))
}

/// Derivative of a series over real time: central difference over ±1 box, one-sided at the ends;
/// zero for a single box or a zero time step.
pub fn derivative(x: &[f64], t: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|i| {
            let (a, b) = diff_span(i, n);
            let dt = t[b] - t[a];
            if b == a || dt <= 0.0 {
                0.0
            } else {
                (x[b] - x[a]) / dt
            }
        })
        .collect()
}

fn derivative_2d(x: &[[f64; 2]], t: &[f64]) -> Vec<[f64; 2]> {
    let xs: Vec<f64> = x.iter().map(|p| p[0]).collect();
    let ys: Vec<f64> = x.iter().map(|p| p[1]).collect();
    derivative(&xs, t)
        .into_iter()
        .zip(derivative(&ys, t))
        .map(|(a, b)| [a, b])
        .collect()
}

/// Wraps an angle (radians) into (-π, π].
pub fn wrap_angle(a: f64) -> f64 {
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut r = a.rem_euclid(two_pi);
    if r > std::f64::consts::PI {
        r -= two_pi;
    }
    r
}

/// Yaw rate (deg/s) by central difference of the heading over real time, each step wrapped.
fn yaw_rate_deg_s(yaw: &[f64], t: &[f64]) -> Vec<f64> {
    let n = yaw.len();
    (0..n)
        .map(|i| {
            let (a, b) = diff_span(i, n);
            let dt = t[b] - t[a];
            if b == a || dt <= 0.0 {
                return 0.0;
            }
            // Sum of wrapped single steps, so a ±1 central difference never jumps by 2π.
            let dyaw: f64 = (a..b).map(|k| wrap_angle(yaw[k + 1] - yaw[k])).sum();
            dyaw.to_degrees() / dt
        })
        .collect()
}

/// Diagonal of the axis-aligned bounding box of a set of points (0 for none).
fn bbox_diagonal(p: &[[f64; 2]]) -> f64 {
    if p.is_empty() {
        return 0.0;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in p {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (hi[0] - lo[0]).hypot(hi[1] - lo[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_median_window_spans_the_same_time_at_any_rate() {
        let at = |hz: f64, n: usize| (0..n).map(|i| i as f64 / hz).collect::<Vec<f64>>();
        // AV2 sweeps are about 99.7 ms apart.
        let av2: Vec<f64> = (0..50).map(|i| i as f64 * 0.0997).collect();
        assert_eq!(median_window(&av2), MEDIAN_WINDOW);
        assert_eq!(median_window(&at(10.0, 50)), 7);
        assert_eq!(median_window(&at(5.0, 50)), 3);
        assert_eq!(median_window(&at(2.0, 50)), 1);
        assert_eq!(median_window(&at(20.0, 50)), 7);
        assert_eq!(median_window(&[0.0]), MEDIAN_WINDOW);
    }

    #[test]
    fn median_filter_truncates_at_ends_and_removes_spikes() {
        let x = [1.0, 2.0, 3.0, 100.0, 5.0, 6.0, 7.0, 8.0];
        let m = median_filter(&x, 7);
        assert_eq!(m[3], 5.0);
        // Ends: the window shrinks symmetrically, so the first value stays and the second is the
        // median of [1, 2, 3]; never pulled towards 0.
        assert_eq!(m[0], 1.0);
        assert_eq!(m[1], 2.0);
        assert_eq!(m[2], 3.0);
        assert_eq!(median_filter(&[4.0, 9.0], 7), vec![4.0, 9.0]);
        assert!(median_filter(&[], 7).is_empty());
    }

    #[test]
    fn derivative_uses_real_time_steps() {
        // A missing frame: t = 0, 0.1, 0.3; x moves 1 m per 0.1 s.
        let d = derivative(&[0.0, 1.0, 3.0], &[0.0, 0.1, 0.3]);
        for v in d {
            assert!((v - 10.0).abs() < 1e-9, "{v}");
        }
        assert_eq!(derivative(&[5.0], &[0.0]), vec![0.0]);
    }

    #[test]
    fn yaw_rate_crosses_pi_without_jumping() {
        let yaw = [3.1, -3.1, -3.0];
        let r = yaw_rate_deg_s(&yaw, &[0.0, 0.1, 0.2]);
        for w in r {
            assert!(w > 0.0 && w < 1000.0, "{w}");
        }
    }
}
