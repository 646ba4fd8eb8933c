//! Plane geometry on x-y points: polygons (containment, distances), polylines, angles.

/// A point in the ground plane (city frame x, y), metres.
pub type Pt = [f64; 2];

/// A simple polygon in the ground plane (not closed: the last point joins the first).
#[derive(Debug, Clone, PartialEq)]
pub struct Polygon {
    /// The vertices, in order.
    pub pts: Vec<Pt>,
    /// Axis-aligned bounds: `[min, max]`.
    pub bbox: [Pt; 2],
}

impl Polygon {
    /// A polygon from its vertices (a repeated closing vertex is harmless).
    pub fn new(pts: Vec<Pt>) -> Polygon {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in &pts {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if pts.is_empty() {
            lo = [0.0; 2];
            hi = [0.0; 2];
        }
        Polygon {
            pts,
            bbox: [lo, hi],
        }
    }

    /// The edges as point pairs (closing edge included).
    pub fn edges(&self) -> impl Iterator<Item = (Pt, Pt)> + '_ {
        let n = self.pts.len();
        (0..n).map(move |i| (self.pts[i], self.pts[(i + 1) % n]))
    }

    /// Whether `p` lies inside (even-odd rule; fewer than 3 vertices contain nothing).
    pub fn contains(&self, p: Pt) -> bool {
        if self.pts.len() < 3
            || p[0] < self.bbox[0][0]
            || p[0] > self.bbox[1][0]
            || p[1] < self.bbox[0][1]
            || p[1] > self.bbox[1][1]
        {
            return false;
        }
        let mut inside = false;
        for (a, b) in self.edges() {
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if p[0] < x {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Distance from `p` to the polygon, 0 inside.
    pub fn distance_to_point(&self, p: Pt) -> f64 {
        if self.contains(p) {
            return 0.0;
        }
        self.edges()
            .map(|(a, b)| point_segment_distance2(p, a, b))
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    /// Whether the two polygons' bounding boxes overlap.
    pub fn bbox_overlaps(&self, other: &Polygon) -> bool {
        self.bbox[0][0] <= other.bbox[1][0]
            && other.bbox[0][0] <= self.bbox[1][0]
            && self.bbox[0][1] <= other.bbox[1][1]
            && other.bbox[0][1] <= self.bbox[1][1]
    }

    /// Distance between two polygons' areas, 0 when they overlap or touch.
    pub fn distance_to_polygon(&self, other: &Polygon) -> f64 {
        if self.pts.is_empty() || other.pts.is_empty() {
            return f64::INFINITY;
        }
        let may_overlap = self.bbox_overlaps(other);
        if may_overlap
            && (other.pts.iter().any(|&p| self.contains(p))
                || self.pts.iter().any(|&p| other.contains(p)))
        {
            return 0.0;
        }
        let mut best = f64::INFINITY;
        for (a, b) in self.edges() {
            for (c, d) in other.edges() {
                if may_overlap && segments_intersect(a, b, c, d) {
                    return 0.0;
                }
                best = best
                    .min(point_segment_distance2(a, c, d))
                    .min(point_segment_distance2(b, c, d))
                    .min(point_segment_distance2(c, a, b))
                    .min(point_segment_distance2(d, a, b));
            }
        }
        best.sqrt()
    }

    /// Distance between the polygon's bounding box and `p` (a lower bound of the true distance).
    pub fn bbox_distance(&self, p: Pt) -> f64 {
        let dx = (self.bbox[0][0] - p[0])
            .max(p[0] - self.bbox[1][0])
            .max(0.0);
        let dy = (self.bbox[0][1] - p[1])
            .max(p[1] - self.bbox[1][1])
            .max(0.0);
        dx.hypot(dy)
    }
}

/// Distance from `p` to the segment `a`-`b`.
pub fn point_segment_distance(p: Pt, a: Pt, b: Pt) -> f64 {
    point_segment_distance2(p, a, b).sqrt()
}

/// Squared distance from `p` to the segment `a`-`b`.
pub fn point_segment_distance2(p: Pt, a: Pt, b: Pt) -> f64 {
    let (q, _) = closest_on_segment(p, a, b);
    let (dx, dy) = (p[0] - q[0], p[1] - q[1]);
    dx * dx + dy * dy
}

/// The point of segment `a`-`b` closest to `p`, and its parameter in [0, 1].
pub fn closest_on_segment(p: Pt, a: Pt, b: Pt) -> (Pt, f64) {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ([a[0] + t * d[0], a[1] + t * d[1]], t)
}

fn cross(o: Pt, a: Pt, b: Pt) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Whether segments `a`-`b` and `c`-`d` intersect properly (collinear overlaps count via the
/// endpoint distances of the caller).
pub fn segments_intersect(a: Pt, b: Pt, c: Pt, d: Pt) -> bool {
    let d1 = cross(c, d, a);
    let d2 = cross(c, d, b);
    let d3 = cross(a, b, c);
    let d4 = cross(a, b, d);
    ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
}

/// The four corners of an oriented rectangle (centre, heading in radians, length along the
/// heading, width across), counter-clockwise.
pub fn box_corners(c: Pt, yaw: f64, length: f64, width: f64) -> [Pt; 4] {
    let (s, co) = yaw.sin_cos();
    let (hl, hw) = (0.5 * length, 0.5 * width);
    let f = [co * hl, s * hl];
    let l = [-s * hw, co * hw];
    [
        [c[0] + f[0] - l[0], c[1] + f[1] - l[1]],
        [c[0] + f[0] + l[0], c[1] + f[1] + l[1]],
        [c[0] - f[0] + l[0], c[1] - f[1] + l[1]],
        [c[0] - f[0] - l[0], c[1] - f[1] - l[1]],
    ]
}

/// Total length of a polyline.
pub fn polyline_length(p: &[Pt]) -> f64 {
    p.windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum()
}

/// A polyline resampled to `n >= 2` points evenly spaced by arc length.
pub fn resample(p: &[Pt], n: usize) -> Vec<Pt> {
    if p.is_empty() {
        return Vec::new();
    }
    if p.len() == 1 || n < 2 {
        return vec![p[0]; n.max(1)];
    }
    let mut cum = vec![0.0];
    for w in p.windows(2) {
        let l = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        cum.push(cum.last().copied().unwrap_or(0.0) + l);
    }
    let total = cum.last().copied().unwrap_or(0.0);
    let mut out = Vec::with_capacity(n);
    let mut seg = 0;
    for i in 0..n {
        let s = total * i as f64 / (n - 1) as f64;
        while seg + 2 < cum.len() && cum[seg + 1] < s {
            seg += 1;
        }
        let l = cum[seg + 1] - cum[seg];
        let t = if l > 0.0 {
            ((s - cum[seg]) / l).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (a, b) = (p[seg], p[seg + 1]);
        out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
    }
    out
}

/// Heading (radians) of the vector from `a` to `b`.
pub fn heading(a: Pt, b: Pt) -> f64 {
    (b[1] - a[1]).atan2(b[0] - a[0])
}

/// Nearest point of a polyline to `p`: (segment index, closest point, distance). `None` when the
/// polyline has fewer than 2 points.
pub fn nearest_on_polyline(line: &[Pt], p: Pt) -> Option<(usize, Pt, f64)> {
    let mut best: Option<(usize, Pt, f64)> = None;
    for (i, w) in line.windows(2).enumerate() {
        let (q, _) = closest_on_segment(p, w[0], w[1]);
        let d = (p[0] - q[0]).hypot(p[1] - q[1]);
        if best.is_none_or(|b| d < b.2) {
            best = Some((i, q, d));
        }
    }
    best
}

/// Signed distance of `p` from a polyline: positive on its left (looking along it), negative on
/// its right, measured from the nearest segment. `None` for fewer than 2 points.
pub fn signed_offset(line: &[Pt], p: Pt) -> Option<f64> {
    let (i, _, d) = nearest_on_polyline(line, p)?;
    let side = cross(line[i], line[i + 1], p);
    Some(if side >= 0.0 { d } else { -d })
}

/// Signed distance of `p` from the line through the polyline's segment nearest to it: positive on
/// its left (looking along it), negative on its right. Unlike [`signed_offset`], a point past an
/// end is measured square to the end segment's line (a box corner beyond the last vertex is as
/// far across the line as it looks). `None` for fewer than 2 points or a zero-length segment.
pub fn lateral_offset(line: &[Pt], p: Pt) -> Option<f64> {
    let (i, _, _) = nearest_on_polyline(line, p)?;
    let (a, b) = (line[i], line[i + 1]);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    (len > 0.0).then(|| cross(a, b, p) / len)
}

/// Distance from the segment `a`-`b` to a polygon's area: 0 when it touches or enters it.
pub fn segment_polygon_distance(a: Pt, b: Pt, poly: &Polygon) -> f64 {
    if poly.contains(a) || poly.contains(b) {
        return 0.0;
    }
    let mut best = f64::INFINITY;
    for (c, d) in poly.edges() {
        if segments_intersect(a, b, c, d) {
            return 0.0;
        }
        best = best
            .min(point_segment_distance2(c, a, b))
            .min(point_segment_distance2(a, c, d))
            .min(point_segment_distance2(b, c, d));
    }
    best.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Polygon {
        Polygon::new(vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    }

    #[test]
    fn containment_and_distances() {
        let s = square();
        assert!(s.contains([1.0, 1.0]));
        assert!(!s.contains([3.0, 1.0]));
        assert_eq!(s.distance_to_point([1.0, 1.0]), 0.0);
        assert!((s.distance_to_point([5.0, 1.0]) - 3.0).abs() < 1e-12);
        let far = Polygon::new(vec![[4.0, 0.0], [5.0, 0.0], [5.0, 1.0], [4.0, 1.0]]);
        assert!((s.distance_to_polygon(&far) - 2.0).abs() < 1e-12);
        let cross_shape = Polygon::new(vec![[-1.0, 0.5], [3.0, 0.5], [3.0, 1.5], [-1.0, 1.5]]);
        assert_eq!(s.distance_to_polygon(&cross_shape), 0.0);
    }

    #[test]
    fn resample_and_offsets() {
        let line = [[0.0, 0.0], [10.0, 0.0]];
        let r = resample(&line, 3);
        assert_eq!(r, vec![[0.0, 0.0], [5.0, 0.0], [10.0, 0.0]]);
        assert_eq!(signed_offset(&line, [3.0, 2.0]), Some(2.0));
        assert_eq!(signed_offset(&line, [3.0, -1.5]), Some(-1.5));
        let c = box_corners([0.0, 0.0], std::f64::consts::FRAC_PI_2, 4.0, 2.0);
        assert!((c[0][1] - 2.0).abs() < 1e-12 && (c[0][0] - 1.0).abs() < 1e-12);
    }
}
