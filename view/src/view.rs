//! The mapping from the city frame (metres) to picture pixels: a centre, a heading that points
//! up, and a scale.

/// A bird's-eye view: which city point is at the picture's centre, which heading points up,
/// and how many pixels a metre is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// The city point at the centre of the map area.
    pub center: [f64; 2],
    /// The city-frame heading (radians) that points up in the picture.
    pub heading: f64,
    /// Pixels per metre.
    pub scale: f64,
    /// Pixel position of the centre.
    pub origin: [f64; 2],
    /// Half the map area's diagonal, metres: what lies further from the centre is not drawn.
    pub radius: f64,
}

impl View {
    /// A view centred on `center` with `heading` up, showing `half_extent` metres either side
    /// of the centre in the part of a `width` × `height` picture below `top` pixels (the
    /// header); the whole picture is still drawn.
    pub fn new(
        center: [f64; 2],
        heading: f64,
        half_extent: f64,
        width: f64,
        height: f64,
        top: f64,
    ) -> View {
        let half = half_extent.max(1.0);
        let top = top.clamp(0.0, height / 2.0);
        let scale = width.min(height - top) / (2.0 * half);
        View {
            center,
            heading,
            scale,
            origin: [width / 2.0, top + (height - top) / 2.0],
            radius: (width.hypot(height) / 2.0) / scale,
        }
    }

    /// The pixel of a city point.
    pub fn px(&self, p: [f64; 2]) -> [f64; 2] {
        let dx = p[0] - self.center[0];
        let dy = p[1] - self.center[1];
        let (s, c) = self.heading.sin_cos();
        let forward = dx * c + dy * s;
        let left = -dx * s + dy * c;
        [
            self.origin[0] - left * self.scale,
            self.origin[1] - forward * self.scale,
        ]
    }

    /// Whether any of `points` lies within the view's radius (plus `margin` metres), or the
    /// points' bounding box covers the centre.
    pub fn touches(&self, points: &[[f64; 2]], margin: f64) -> bool {
        let r = self.radius + margin;
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            let d = (p[0] - self.center[0]).hypot(p[1] - self.center[1]);
            if d <= r {
                return true;
            }
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        // A large polygon (a drivable area) can hold the view without a vertex near it.
        !points.is_empty()
            && lo[0] - r <= self.center[0]
            && self.center[0] <= hi[0] + r
            && lo[1] - r <= self.center[1]
            && self.center[1] <= hi[1] + r
    }

    /// The picture direction (unit vector, pixels, y down) of a city-frame heading.
    pub fn direction(&self, heading: f64) -> [f64; 2] {
        let a = self.px([
            self.center[0] + heading.cos(),
            self.center[1] + heading.sin(),
        ]);
        [
            (a[0] - self.origin[0]) / self.scale,
            (a[1] - self.origin[1]) / self.scale,
        ]
    }
}
