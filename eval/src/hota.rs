//! HOTA as TrackEval computes it, for one class over several sequences.

/// The 19 alpha thresholds 0.05, 0.10, ... 0.95 (as numpy's `arange(0.05, 0.99, 0.05)`).
pub fn alphas() -> [f64; 19] {
    let mut a = [0.0; 19];
    for (i, x) in a.iter_mut().enumerate() {
        *x = 0.05 + i as f64 * 0.05;
    }
    a
}

const EPS: f64 = f64::EPSILON;

/// One frame of one class: object ids and xy centres.
#[derive(Debug, Clone, Default)]
pub struct ClassFrame {
    /// Track ids.
    pub ids: Vec<i32>,
    /// xy centres.
    pub xy: Vec<[f64; 2]>,
}

/// HOTA sums for one class, per alpha.
#[derive(Debug, Clone, PartialEq)]
pub struct Hota {
    /// True positives per alpha.
    pub tp: [f64; 19],
    /// False negatives per alpha.
    pub fn_: [f64; 19],
    /// False positives per alpha.
    pub fp: [f64; 19],
    /// Association accuracy per alpha.
    pub ass_a: [f64; 19],
    /// Localisation accuracy per alpha.
    pub loc_a: [f64; 19],
    /// Detection accuracy per alpha.
    pub det_a: [f64; 19],
    /// HOTA per alpha.
    pub hota: [f64; 19],
}

impl Hota {
    /// Mean HOTA over the alphas, summed in numpy's order (8 running partial sums, then the rest).
    pub fn mean(&self) -> f64 {
        np_sum(&self.hota) / 19.0
    }
}

/// Similarity max(0, 1 - d/2) on xy distance.
pub fn similarity(a: &[[f64; 2]], b: &[[f64; 2]]) -> Vec<Vec<f64>> {
    a.iter()
        .map(|p| {
            b.iter()
                .map(|q| {
                    let dx = p[0] - q[0];
                    let dy = p[1] - q[1];
                    let d = (dx * dx + dy * dy).sqrt();
                    (1.0 - d / 2.0).max(0.0)
                })
                .collect()
        })
        .collect()
}

/// Maximising assignment, scipy's `linear_sum_assignment(-m)`: (rows, cols).
pub fn max_assignment(m: &[Vec<f64>]) -> (Vec<usize>, Vec<usize>) {
    let nr = m.len();
    let nc = m.first().map_or(0, |r| r.len());
    if nr == 0 || nc == 0 {
        return (Vec::new(), Vec::new());
    }
    let flat: Vec<f64> = m.iter().flat_map(|r| r.iter().map(|&x| -x)).collect();
    match lsap::solve(nr, nc, &flat, false) {
        Ok((r, c)) => (r, c),
        Err(_) => (Vec::new(), Vec::new()),
    }
}

struct SeqRes {
    tp: [f64; 19],
    fn_: [f64; 19],
    fp: [f64; 19],
    ass_a: [f64; 19],
    loc_a: [f64; 19],
}

fn map_ids(frames: &[&ClassFrame]) -> (Vec<Vec<usize>>, usize) {
    let mut map = std::collections::HashMap::new();
    let out = frames
        .iter()
        .map(|f| {
            f.ids
                .iter()
                .map(|id| {
                    let n = map.len();
                    *map.entry(*id).or_insert(n)
                })
                .collect()
        })
        .collect();
    (out, map.len())
}

#[allow(clippy::needless_range_loop)]
fn eval_sequence(gt: &[ClassFrame], tr: &[ClassFrame]) -> SeqRes {
    let mut r = SeqRes {
        tp: [0.0; 19],
        fn_: [0.0; 19],
        fp: [0.0; 19],
        ass_a: [0.0; 19],
        loc_a: [0.0; 19],
    };
    let n_gt_dets: usize = gt.iter().map(|f| f.ids.len()).sum();
    let n_tr_dets: usize = tr.iter().map(|f| f.ids.len()).sum();
    if n_tr_dets == 0 {
        r.fn_ = [n_gt_dets as f64; 19];
        r.loc_a = [1.0; 19];
        return r;
    }
    if n_gt_dets == 0 {
        r.fp = [n_tr_dets as f64; 19];
        r.loc_a = [1.0; 19];
        return r;
    }
    let (gids, ng) = map_ids(&gt.iter().collect::<Vec<_>>());
    let (tids, nt) = map_ids(&tr.iter().collect::<Vec<_>>());
    let sims: Vec<Vec<Vec<f64>>> = gt
        .iter()
        .zip(tr)
        .map(|(g, t)| similarity(&g.xy, &t.xy))
        .collect();
    let mut pot = vec![0.0f64; ng * nt];
    let mut gcount = vec![0.0f64; ng];
    let mut tcount = vec![0.0f64; nt];
    for (t, sim) in sims.iter().enumerate() {
        let (g, k) = (&gids[t], &tids[t]);
        let colsum: Vec<f64> = (0..k.len())
            .map(|j| sim.iter().map(|row| row[j]).sum())
            .collect();
        for (i, row) in sim.iter().enumerate() {
            let rowsum: f64 = row.iter().sum();
            for (j, &s) in row.iter().enumerate() {
                let denom = colsum[j] + rowsum - s;
                if denom > EPS {
                    pot[g[i] * nt + k[j]] += s / denom;
                }
            }
        }
        for &i in g {
            gcount[i] += 1.0;
        }
        for &j in k {
            tcount[j] += 1.0;
        }
    }
    let gas: Vec<f64> = (0..ng * nt)
        .map(|x| pot[x] / (gcount[x / nt] + tcount[x % nt] - pot[x]))
        .collect();
    let al = alphas();
    let mut matches = vec![vec![0.0f64; ng * nt]; 19];
    for (t, sim) in sims.iter().enumerate() {
        let (g, k) = (&gids[t], &tids[t]);
        if g.is_empty() {
            for a in 0..19 {
                r.fp[a] += k.len() as f64;
            }
            continue;
        }
        if k.is_empty() {
            for a in 0..19 {
                r.fn_[a] += g.len() as f64;
            }
            continue;
        }
        let score: Vec<Vec<f64>> = sim
            .iter()
            .enumerate()
            .map(|(i, row)| {
                row.iter()
                    .enumerate()
                    .map(|(j, &s)| gas[g[i] * nt + k[j]] * s)
                    .collect()
            })
            .collect();
        let (rows, cols) = max_assignment(&score);
        for (a, &alpha) in al.iter().enumerate() {
            let mut num = 0usize;
            let mut loc = 0.0f64;
            for (&i, &j) in rows.iter().zip(&cols) {
                let s = sim[i][j];
                if s >= alpha - EPS {
                    num += 1;
                    loc += s;
                    matches[a][g[i] * nt + k[j]] += 1.0;
                }
            }
            r.tp[a] += num as f64;
            r.fn_[a] += (g.len() - num) as f64;
            r.fp[a] += (k.len() - num) as f64;
            if num > 0 {
                r.loc_a[a] += loc;
            }
        }
    }
    for a in 0..19 {
        let mut s = 0.0;
        for (x, &m) in matches[a].iter().enumerate() {
            if m > 0.0 {
                let ass = m / (gcount[x / nt] + tcount[x % nt] - m).max(1.0);
                s += m * ass;
            }
        }
        r.ass_a[a] = s / r.tp[a].max(1.0);
        r.loc_a[a] = r.loc_a[a].max(1e-10) / r.tp[a].max(1e-10);
    }
    r
}

/// HOTA for one class over sequences (each a pair of aligned gt/tracker frame lists), combined as TrackEval's
/// `COMBINED_SEQ`.
#[allow(clippy::needless_range_loop)]
pub fn hota<G: AsRef<[ClassFrame]>>(seqs: &[(G, Vec<ClassFrame>)]) -> Hota {
    let res: Vec<SeqRes> = seqs
        .iter()
        .map(|(g, t)| eval_sequence(g.as_ref(), t))
        .collect();
    let mut h = Hota {
        tp: [0.0; 19],
        fn_: [0.0; 19],
        fp: [0.0; 19],
        ass_a: [0.0; 19],
        loc_a: [0.0; 19],
        det_a: [0.0; 19],
        hota: [0.0; 19],
    };
    for a in 0..19 {
        for r in &res {
            h.tp[a] += r.tp[a];
            h.fn_[a] += r.fn_[a];
            h.fp[a] += r.fp[a];
        }
        let ass: f64 = res.iter().map(|r| r.ass_a[a] * r.tp[a]).sum();
        h.ass_a[a] = ass / h.tp[a].max(1.0);
        let loc: f64 = res.iter().map(|r| r.loc_a[a] * r.tp[a]).sum();
        h.loc_a[a] = loc.max(1e-10) / h.tp[a].max(1e-10);
        h.det_a[a] = h.tp[a] / (h.tp[a] + h.fn_[a] + h.fp[a]).max(1.0);
        h.hota[a] = (h.det_a[a] * h.ass_a[a]).sqrt();
    }
    h
}

/// numpy's pairwise sum for fewer than 128 values: 8 partial sums over blocks of 8, combined pairwise, then
/// the remainder added in order.
pub fn np_sum(v: &[f64]) -> f64 {
    if v.len() < 8 {
        return v.iter().fold(0.0, |a, &x| a + x);
    }
    let mut r = [0.0f64; 8];
    r.copy_from_slice(&v[..8]);
    let blocks = v.len() - v.len() % 8;
    let mut i = 8;
    while i < blocks {
        for j in 0..8 {
            r[j] += v[i + j];
        }
        i += 8;
    }
    let mut res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
    for &x in &v[blocks..] {
        res += x;
    }
    res
}
