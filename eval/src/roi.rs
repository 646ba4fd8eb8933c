//! The drivable-area region-of-interest (ROI) filter of the official evaluation (av2 0.3.6, `--dataset_dir`).
//!
//! What the official code does, and what this module reproduces exactly:
//! - The raster is computed from the log's vector map (`<log>/map/log_map_archive_*.json`, its
//!   `drivable_areas` polygons); no stored image is read. The `*___img_Sim2_city.json` file beside the
//!   map belongs to the ground-height raster (30 cm) and is not used for the ROI.
//! - Grid: 0.1 m cells. Bounds are floor/ceil of the minimum/maximum vertex x and y over all drivable
//!   areas; the grid is `(y_max - y_min + 1) * 10` rows by `(x_max - x_min + 1) * 10` columns; city to
//!   grid is `p_grid = 10 * (p_city - (x_min, y_min))`.
//! - Each polygon's vertices are mapped to the grid and rounded half to even, then filled with Pillow's
//!   `ImageDraw.polygon(fill=1, outline=1)`. Since fill and outline inks are equal, Pillow draws only the
//!   filled polygon; its scan-line filler (edge rows in `f32`, the "consistent polygons" and
//!   "discontiguous corners" rules, horizontal edges drawn as lines) is reimplemented here.
//! - The ROI is every cell whose Euclidean distance to the nearest drivable cell is at most 5 m = 50 cells
//!   (OpenCV's exact L2 distance transform, thresholded with `<=`), within the grid.
//! - A box is kept when any of its 8 corners (centre, length/width/height, yaw about z, all in the city
//!   frame) falls in an ROI cell: grid coordinates are truncated toward zero (`astype(int64)`), and corners
//!   outside the grid are outside the ROI.
//!
//! Owns: reading the drivable areas of a map, building the ROI raster, testing boxes, and [`RoiMaps`]
//! (one raster per log of a dataset directory).

use crate::error::EvalError;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Grid cells per metre (0.1 m cells).
pub const CELLS_PER_M: f64 = 10.0;

/// How far the ROI reaches beyond the drivable area, in cells (5 m).
pub const ROI_DILATION_CELLS: i64 = 50;

/// Largest grid accepted (cells); a map beyond it is reported as an error instead of exhausting memory.
const MAX_CELLS: u64 = 1_000_000_000;

/// A row-major bit set of `width * height` cells.
#[derive(Clone)]
struct Bits {
    words: Vec<u64>,
}

impl Bits {
    fn new(cells: usize) -> Bits {
        Bits {
            words: vec![0; cells.div_ceil(64)],
        }
    }

    fn get(&self, i: usize) -> bool {
        self.words[i / 64] >> (i % 64) & 1 == 1
    }

    fn set(&mut self, i: usize) {
        self.words[i / 64] |= 1 << (i % 64);
    }

    fn count(&self) -> u64 {
        self.words.iter().map(|w| u64::from(w.count_ones())).sum()
    }
}

/// The ROI raster of one log.
#[derive(Clone)]
pub struct RoiRaster {
    width: usize,
    height: usize,
    x_min: i64,
    y_min: i64,
    x_max: i64,
    y_max: i64,
    drivable: Bits,
    roi: Bits,
    polygons: usize,
}

impl std::fmt::Debug for RoiRaster {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RoiRaster")
            .field("bounds", &self.bounds())
            .field("height", &self.height)
            .field("width", &self.width)
            .field("drivable_cells", &self.drivable.count())
            .field("polygons", &self.polygons)
            .finish()
    }
}

/// An edge of Pillow's polygon filler.
#[derive(Clone, Copy)]
struct Edge {
    x0: i32,
    y0: i32,
    xmin: i32,
    ymin: i32,
    xmax: i32,
    ymax: i32,
    dx: f32,
}

impl Edge {
    fn new(x0: i32, y0: i32, x1: i32, y1: i32) -> Edge {
        let dx = if y0 == y1 {
            0.0
        } else {
            (x1 - x0) as f32 / (y1 - y0) as f32
        };
        Edge {
            x0,
            y0,
            xmin: x0.min(x1),
            xmax: x0.max(x1),
            ymin: y0.min(y1),
            ymax: y0.max(y1),
            dx,
        }
    }

    /// The edge's x on row `y`, in `f32` as Pillow computes it.
    fn x_at(&self, y: i32) -> f32 {
        (y - self.y0) as f32 * self.dx + self.x0 as f32
    }
}

/// Rounds half away from zero as Pillow's `ROUND_UP`.
fn round_up(f: f32) -> i32 {
    if f >= 0.0 {
        (f + 0.5).floor() as i32
    } else {
        -((f.abs() + 0.5).floor() as i32)
    }
}

/// Rounds half toward zero as Pillow's `ROUND_DOWN`.
fn round_down(f: f32) -> i32 {
    if f >= 0.0 {
        (f - 0.5).ceil() as i32
    } else {
        -((f.abs() - 0.5).ceil() as i32)
    }
}

/// An 8-bit single-channel canvas (0/1).
struct Canvas {
    width: i32,
    height: i32,
    cells: Vec<u8>,
}

impl Canvas {
    fn hline(&mut self, x0: i32, y: i32, x1: i32) {
        if y < 0 || y >= self.height || x0 >= self.width || x1 < 0 {
            return;
        }
        let x0 = x0.max(0);
        let x1 = x1.min(self.width - 1);
        if x0 <= x1 {
            let row = y as usize * self.width as usize;
            self.cells[row + x0 as usize..=row + x1 as usize].fill(1);
        }
    }

    /// Fills a polygon given by integer vertices as Pillow's `ImagingDrawPolygon(fill=1)`.
    fn fill_polygon(&mut self, pts: &[(i32, i32)]) {
        let count = pts.len();
        if count == 0 {
            return;
        }
        let mut edges: Vec<Edge> = Vec::with_capacity(count);
        for i in 0..count - 1 {
            let (x0, y0) = pts[i];
            let (x1, y1) = pts[i + 1];
            if y0 == y1 && i != 0 && y0 == pts[i - 1].1 {
                // a horizontal segment right after another one extends it when both run the same way
                let prev_x = pts[i - 1].0;
                if let Some(last) = edges.last_mut() {
                    if x1 > x0 && x0 > prev_x {
                        last.xmax = x1;
                        continue;
                    } else if x1 < x0 && x0 < prev_x {
                        last.xmin = x1;
                        continue;
                    }
                }
            }
            edges.push(Edge::new(x0, y0, x1, y1));
        }
        if pts[count - 1] != pts[0] {
            let (x0, y0) = pts[count - 1];
            let (x1, y1) = pts[0];
            edges.push(Edge::new(x0, y0, x1, y1));
        }
        self.scan(&edges);
    }

    /// Pillow's `polygon_generic` for an 8-bit image without alpha.
    fn scan(&mut self, edges: &[Edge]) {
        if edges.is_empty() {
            return;
        }
        let mut ymin = self.height - 1;
        let mut ymax = 0;
        let mut table: Vec<Edge> = Vec::with_capacity(edges.len());
        for e in edges {
            ymin = ymin.min(e.ymin);
            ymax = ymax.max(e.ymax);
            if e.ymin == e.ymax {
                self.hline(e.xmin, e.ymin, e.xmax);
                continue;
            }
            table.push(*e);
        }
        ymin = ymin.max(0);
        ymax = ymax.min(self.height);
        let mut xx: Vec<f32> = Vec::with_capacity(table.len() * 2);
        for y in ymin..=ymax {
            xx.clear();
            for (i, cur) in table.iter().enumerate() {
                if y < cur.ymin || y > cur.ymax {
                    continue;
                }
                xx.push(cur.x_at(y));
                let j = xx.len();
                if y == cur.ymax && y < ymax {
                    // needed to draw consistent polygons
                    xx.push(xx[j - 1]);
                } else if (y == cur.ymin || y == cur.ymax) && cur.dx != 0.0 {
                    // connect discontiguous corners
                    for other in &table[..i] {
                        if (y != other.ymin && y != other.ymax) || other.dx == 0.0 {
                            continue;
                        }
                        if xx[j - 1].round() != other.x_at(y).round() {
                            continue;
                        }
                        let offset = if y == cur.ymax { -1 } else { 1 };
                        let adjacent = cur.x_at(y + offset);
                        if y + offset >= other.ymin && y + offset <= other.ymax {
                            let adjacent_other = other.x_at(y + offset);
                            let x = xx[j - 1];
                            if x > adjacent + 1.0 && x > adjacent_other + 1.0 {
                                xx[j - 1] = adjacent.max(adjacent_other).round() + 1.0;
                            } else if x < adjacent - 1.0 && x < adjacent_other - 1.0 {
                                xx[j - 1] = adjacent.min(adjacent_other).round() - 1.0;
                            }
                            break;
                        }
                    }
                }
            }
            xx.sort_by(|a, b| a.total_cmp(b));
            let mut i = 1;
            while i < xx.len() {
                self.hline(round_up(xx[i - 1]), y, round_down(xx[i]));
                i += 2;
            }
        }
    }
}

/// Half-widths of the disc of radius [`ROI_DILATION_CELLS`]: entry `g` is the largest `h` with
/// `g² + h² <= r²`.
fn disc_half_widths() -> Vec<i64> {
    let r = ROI_DILATION_CELLS;
    (0..=r)
        .map(|g| {
            let mut h = 0;
            while g * g + (h + 1) * (h + 1) <= r * r {
                h += 1;
            }
            h
        })
        .collect()
}

/// Cells within Euclidean distance [`ROI_DILATION_CELLS`] of a drivable cell (exact, integer arithmetic).
fn dilate(drivable: &[u8], width: usize, height: usize) -> Bits {
    let r = ROI_DILATION_CELLS as u8;
    let none = r + 1;
    // vertical distance to the nearest drivable cell above (inclusive), capped at r + 1
    let mut up = vec![none; width * height];
    let mut run = vec![none; width];
    for y in 0..height {
        let row = &drivable[y * width..(y + 1) * width];
        for x in 0..width {
            run[x] = if row[x] != 0 {
                0
            } else {
                run[x].saturating_add(1).min(none)
            };
        }
        up[y * width..(y + 1) * width].copy_from_slice(&run);
    }
    let half = disc_half_widths();
    let mut roi = Bits::new(width * height);
    let mut diff = vec![0i32; width + 1];
    run.fill(none);
    for y in (0..height).rev() {
        let row = &drivable[y * width..(y + 1) * width];
        diff.fill(0);
        let mut any = false;
        for x in 0..width {
            run[x] = if row[x] != 0 {
                0
            } else {
                run[x].saturating_add(1).min(none)
            };
            let g = run[x].min(up[y * width + x]);
            if g <= r {
                let h = half[g as usize];
                let lo = (x as i64 - h).max(0) as usize;
                let hi = ((x as i64 + h) as usize).min(width - 1);
                diff[lo] += 1;
                diff[hi + 1] -= 1;
                any = true;
            }
        }
        if !any {
            continue;
        }
        let mut acc = 0;
        for (x, d) in diff[..width].iter().enumerate() {
            acc += d;
            if acc > 0 {
                roi.set(y * width + x);
            }
        }
    }
    roi
}

impl RoiRaster {
    /// Builds the raster from drivable-area polygons (city-frame x-y vertices).
    pub fn from_drivable_areas(areas: &[Vec<[f64; 2]>]) -> Result<RoiRaster, EvalError> {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in areas.iter().flatten() {
            for k in 0..2 {
                if !p[k].is_finite() {
                    return Err(EvalError::Format(format!(
                        "drivable area vertex {p:?} is not finite"
                    )));
                }
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if lo[0] > hi[0] {
            return Err(EvalError::Format(
                "the map has no drivable-area vertices".to_string(),
            ));
        }
        let (x_min, y_min) = (lo[0].floor() as i64, lo[1].floor() as i64);
        let (x_max, y_max) = (hi[0].ceil() as i64, hi[1].ceil() as i64);
        let height = ((y_max - y_min + 1) as f64 * CELLS_PER_M) as u64;
        let width = ((x_max - x_min + 1) as f64 * CELLS_PER_M) as u64;
        if width.saturating_mul(height) > MAX_CELLS || width > i32::MAX as u64 / 2 {
            return Err(EvalError::Format(format!(
                "drivable areas span x {x_min}..{x_max}, y {y_min}..{y_max}: a raster of {height} x {width} cells is too large"
            )));
        }
        let (width, height) = (width as usize, height as usize);
        let mut canvas = Canvas {
            width: width as i32,
            height: height as i32,
            cells: vec![0; width * height],
        };
        let (tx, ty) = (-x_min as f64, -y_min as f64);
        for poly in areas {
            let pts: Vec<(i32, i32)> = poly
                .iter()
                .map(|p| {
                    let gx = ((p[0] + tx) * CELLS_PER_M).round_ties_even();
                    let gy = ((p[1] + ty) * CELLS_PER_M).round_ties_even();
                    (gx as i32, gy as i32)
                })
                .collect();
            canvas.fill_polygon(&pts);
        }
        let mut drivable = Bits::new(width * height);
        for (i, &c) in canvas.cells.iter().enumerate() {
            if c != 0 {
                drivable.set(i);
            }
        }
        let roi = dilate(&canvas.cells, width, height);
        Ok(RoiRaster {
            width,
            height,
            x_min,
            y_min,
            x_max,
            y_max,
            drivable,
            roi,
            polygons: areas.len(),
        })
    }

    /// Builds the raster of a log from its map directory (`<log>/map`), which must hold exactly one
    /// `log_map_archive_*.json`.
    pub fn from_map_dir(map_dir: &Path) -> Result<RoiRaster, EvalError> {
        let path = find_vector_map(map_dir)?;
        let areas = read_drivable_areas(&path)?;
        RoiRaster::from_drivable_areas(&areas)
            .map_err(|e| EvalError::Format(format!("{}: {e}", path.display())))
    }

    /// Grid bounds in the city frame: `[x_min, y_min, x_max, y_max]` (whole metres).
    pub fn bounds(&self) -> [i64; 4] {
        [self.x_min, self.y_min, self.x_max, self.y_max]
    }

    /// Grid size as (rows, columns).
    pub fn shape(&self) -> (usize, usize) {
        (self.height, self.width)
    }

    /// Number of drivable-area cells.
    pub fn drivable_cells(&self) -> u64 {
        self.drivable.count()
    }

    /// Number of ROI cells (drivable area grown by 5 m).
    pub fn roi_cells(&self) -> u64 {
        self.roi.count()
    }

    /// Number of drivable-area polygons the raster was built from.
    pub fn polygons(&self) -> usize {
        self.polygons
    }

    /// The grid cell of a city-frame point, as `get_raster_values_at_coords` finds it (coordinates
    /// truncated toward zero); `None` outside the grid.
    fn cell(&self, x: f64, y: f64) -> Option<usize> {
        let gx = (x + -(self.x_min as f64)) * CELLS_PER_M;
        let gy = (y + -(self.y_min as f64)) * CELLS_PER_M;
        if gx.is_nan() || gy.is_nan() {
            return None;
        }
        let (ix, iy) = (gx as i64, gy as i64);
        if ix < 0 || iy < 0 || ix >= self.width as i64 || iy >= self.height as i64 {
            return None;
        }
        Some(iy as usize * self.width + ix as usize)
    }

    /// Whether a city-frame point falls in an ROI cell (outside the grid: no).
    pub fn contains(&self, x: f64, y: f64) -> bool {
        self.cell(x, y).is_some_and(|i| self.roi.get(i))
    }

    /// Whether a city-frame point falls in a drivable-area cell (outside the grid: no).
    pub fn in_drivable_area(&self, x: f64, y: f64) -> bool {
        self.cell(x, y).is_some_and(|i| self.drivable.get(i))
    }

    /// Whether any corner of a box (city-frame centre, length/width/height, yaw about z) is in the ROI.
    pub fn box_in_roi(&self, center: [f64; 3], size: [f32; 3], yaw: f32) -> bool {
        box_corners_xy(center, size, yaw)
            .iter()
            .any(|c| self.contains(c[0], c[1]))
    }
}

/// The x-y of a box's corners (its 8 corners project to these 4), computed as av2's
/// `Cuboid.vertices_m` with the rotation from scipy's `Rotation.from_euler("z", yaw)`.
pub fn box_corners_xy(center: [f64; 3], size: [f32; 3], yaw: f32) -> [[f64; 2]; 4] {
    let half = f64::from(yaw) / 2.0;
    let (qz, qw) = (half.sin(), half.cos());
    let norm = (qz * qz + qw * qw).sqrt();
    let (z, w) = (qz / norm, qw / norm);
    let (z2, w2, zw) = (z * z, w * w, z * w);
    let m00 = -z2 + w2;
    let m01 = 2.0 * -zw;
    let m10 = 2.0 * zw;
    let m11 = -z2 + w2;
    let a = f64::from(size[0]) / 2.0;
    let b = f64::from(size[1]) / 2.0;
    let mut out = [[0.0; 2]; 4];
    for (k, (sa, sb)) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
        .into_iter()
        .enumerate()
    {
        let (u, v) = (sa * a, sb * b);
        out[k] = [
            (u * m00 + v * m01) + center[0],
            (u * m10 + v * m11) + center[1],
        ];
    }
    out
}

/// The one `log_map_archive_*.json` of a map directory.
fn find_vector_map(map_dir: &Path) -> Result<PathBuf, EvalError> {
    let entries =
        std::fs::read_dir(map_dir).map_err(|e| EvalError::Io(map_dir.display().to_string(), e))?;
    let mut found = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| EvalError::Io(map_dir.display().to_string(), e))?;
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with("log_map_archive_") && name.ends_with(".json") {
            found.push(entry.path());
        }
    }
    found.sort();
    match found.len() {
        1 => Ok(found.remove(0)),
        0 => Err(EvalError::Format(format!(
            "{}: no log_map_archive_*.json (the vector map) in this directory",
            map_dir.display()
        ))),
        n => Err(EvalError::Format(format!(
            "{}: {n} log_map_archive_*.json files, expected exactly one",
            map_dir.display()
        ))),
    }
}

/// The drivable-area polygons (x-y of `area_boundary`) of a vector map file, in file order.
pub fn read_drivable_areas(path: &Path) -> Result<Vec<Vec<[f64; 2]>>, EvalError> {
    let text = scenalog_input::read_regular_file(path, scenalog_input::TEXT_LIMIT)
        .map_err(|p| EvalError::File(path.display().to_string(), p))?;
    let doc: serde_json::Value = serde_json::from_slice(&text)
        .map_err(|e| EvalError::Format(format!("{}: not JSON: {e}", path.display())))?;
    let bad = |what: String| EvalError::Format(format!("{}: {what}", path.display()));
    let areas = doc
        .get("drivable_areas")
        .and_then(|v| v.as_object())
        .ok_or_else(|| bad("no \"drivable_areas\" object".to_string()))?;
    let mut out = Vec::with_capacity(areas.len());
    for (id, area) in areas {
        let boundary = area
            .get("area_boundary")
            .and_then(|v| v.as_array())
            .ok_or_else(|| bad(format!("drivable area {id}: no \"area_boundary\" array")))?;
        let mut poly = Vec::with_capacity(boundary.len());
        for (i, p) in boundary.iter().enumerate() {
            let coord = |k: &str| {
                p.get(k).and_then(|v| v.as_f64()).ok_or_else(|| {
                    bad(format!(
                        "drivable area {id}: area_boundary[{i}] has no number \"{k}\""
                    ))
                })
            };
            poly.push([coord("x")?, coord("y")?]);
        }
        out.push(poly);
    }
    Ok(out)
}

/// ROI rasters by log id.
#[derive(Debug, Clone, Default)]
pub struct RoiMaps {
    by_log: BTreeMap<String, Arc<RoiRaster>>,
}

impl RoiMaps {
    /// Builds the rasters of the given logs from a dataset directory holding one directory per log id
    /// (`<dataset_dir>/<log_id>/map/log_map_archive_*.json`), in parallel. A log without a directory there
    /// is an error naming it.
    pub fn load<'a>(
        dataset_dir: &Path,
        log_ids: impl IntoIterator<Item = &'a str>,
    ) -> Result<RoiMaps, EvalError> {
        let mut ids: Vec<&str> = log_ids.into_iter().collect();
        ids.sort_unstable();
        ids.dedup();
        for id in &ids {
            // A submission read by this crate has its ids checked already; ids given otherwise
            // are checked here, so nothing outside the dataset directory is read.
            scenalog_input::check_log_id(id).map_err(EvalError::Format)?;
            let dir = dataset_dir.join(id);
            if !dir.is_dir() {
                return Err(EvalError::Format(format!(
                    "log {id} is not in the dataset directory {} (no directory {})",
                    dataset_dir.display(),
                    dir.display()
                )));
            }
        }
        let built: Result<Vec<(String, Arc<RoiRaster>)>, EvalError> = ids
            .par_iter()
            .map(|id| {
                let raster = RoiRaster::from_map_dir(&dataset_dir.join(id).join("map"))?;
                Ok((id.to_string(), Arc::new(raster)))
            })
            .collect();
        Ok(RoiMaps {
            by_log: built?.into_iter().collect(),
        })
    }

    /// Adds (or replaces) the raster of one log.
    pub fn insert(&mut self, log_id: impl Into<String>, raster: Arc<RoiRaster>) {
        self.by_log.insert(log_id.into(), raster);
    }

    /// The raster of a log.
    pub fn get(&self, log_id: &str) -> Option<&RoiRaster> {
        self.by_log.get(log_id).map(|r| r.as_ref())
    }

    /// The shared raster of a log (to reuse it under another log id without a copy).
    pub fn shared(&self, log_id: &str) -> Option<Arc<RoiRaster>> {
        self.by_log.get(log_id).cloned()
    }

    /// The log ids held.
    pub fn log_ids(&self) -> impl Iterator<Item = &str> {
        self.by_log.keys().map(|s| s.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disc_half_widths_are_exact() {
        let h = disc_half_widths();
        assert_eq!(h[0], 50);
        assert_eq!(h[50], 0);
        assert_eq!(h[30], 40); // 30² + 40² = 50²
        for (g, &w) in h.iter().enumerate() {
            let g = g as i64;
            assert!(g * g + w * w <= 2500 && g * g + (w + 1) * (w + 1) > 2500);
        }
    }

    #[test]
    fn pillow_rounding() {
        assert_eq!(round_up(2.5), 3);
        assert_eq!(round_up(-2.5), -3);
        assert_eq!(round_down(2.5), 2);
        assert_eq!(round_down(-2.5), -2);
        assert_eq!(round_down(2.6), 3);
    }

    #[test]
    fn square_fill_includes_its_boundary() {
        let mut c = Canvas {
            width: 10,
            height: 10,
            cells: vec![0; 100],
        };
        c.fill_polygon(&[(2, 2), (6, 2), (6, 5), (2, 5), (2, 2)]);
        let n: u32 = c.cells.iter().map(|&v| u32::from(v)).sum();
        assert_eq!(n, 5 * 4);
        assert_eq!(c.cells[2 * 10 + 2], 1);
        assert_eq!(c.cells[5 * 10 + 6], 1);
        assert_eq!(c.cells[6 * 10 + 6], 0);
    }

    #[test]
    fn dilation_is_a_disc() {
        let (w, h) = (201, 201);
        let mut d = vec![0u8; w * h];
        d[100 * w + 100] = 1;
        let roi = dilate(&d, w, h);
        let mut n = 0;
        for y in 0..h {
            for x in 0..w {
                let (dx, dy) = (x as i64 - 100, y as i64 - 100);
                let inside = dx * dx + dy * dy <= 2500;
                assert_eq!(roi.get(y * w + x), inside, "{x},{y}");
                n += inside as u64;
            }
        }
        assert_eq!(roi.count(), n);
    }
}
