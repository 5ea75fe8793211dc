//! Graph partitioning with METIS (fixed seed, sorted adjacency) and level-0 / per-group clustering
//! ([`super::Partitioner::Metis`]). GKlib's random generator is process-global (`static` state in
//! `random.c`), so METIS calls are serialized behind a lock for determinism.

use metis::Idx;

/// An undirected weighted graph in CSR form (METIS input).
#[derive(Clone, Debug, Default)]
pub(crate) struct Graph {
    pub xadj: Vec<Idx>,
    pub adj: Vec<Idx>,
    pub w: Vec<Idx>,
}

impl Graph {
    /// Graph over `n` nodes from undirected edges `(a, b, weight)`; duplicates are merged (weights
    /// summed), self loops dropped, adjacency sorted.
    pub fn from_edges(n: usize, edges: &[(u32, u32, i32)]) -> Graph {
        let mut dir: Vec<(u32, u32, i32)> = Vec::with_capacity(edges.len() * 2);
        for &(a, b, w) in edges {
            if a != b {
                dir.push((a, b, w));
                dir.push((b, a, w));
            }
        }
        dir.sort_unstable_by_key(|e| (e.0, e.1));
        let mut g = Graph {
            xadj: Vec::with_capacity(n + 1),
            adj: Vec::new(),
            w: Vec::new(),
        };
        g.xadj.push(0);
        let mut i = 0;
        for node in 0..n as u32 {
            while i < dir.len() && dir[i].0 == node {
                let (_, b, w) = dir[i];
                if g.adj.last() == Some(&(b as Idx))
                    && g.adj.len() > *g.xadj.last().unwrap_or(&0) as usize
                {
                    if let Some(lw) = g.w.last_mut() {
                        *lw = lw.saturating_add(w);
                    }
                } else {
                    g.adj.push(b as Idx);
                    g.w.push(w);
                }
                i += 1;
            }
            g.xadj.push(g.adj.len() as Idx);
        }
        g
    }

    fn node_count(&self) -> usize {
        self.xadj.len().saturating_sub(1)
    }

    /// Subgraph induced by `nodes` (sorted, unique), renumbered 0..nodes.len().
    fn induced(&self, nodes: &[u32]) -> Graph {
        let mut g = Graph {
            xadj: Vec::with_capacity(nodes.len() + 1),
            adj: Vec::new(),
            w: Vec::new(),
        };
        g.xadj.push(0);
        for &n in nodes {
            let (s, e) = (
                self.xadj[n as usize] as usize,
                self.xadj[n as usize + 1] as usize,
            );
            for k in s..e {
                if let Ok(local) = nodes.binary_search(&(self.adj[k] as u32)) {
                    g.adj.push(local as Idx);
                    g.w.push(self.w[k]);
                }
            }
            g.xadj.push(g.adj.len() as Idx);
        }
        g
    }
}

/// METIS seed: fixed for determinism.
const SEED: Idx = 7;

/// METIS (GKlib) keeps its random generator in process-global state: concurrent calls would
/// interleave it and break determinism, so every call holds this lock.
static METIS_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn metis_kway(g: &Graph, nparts: usize) -> Option<Vec<Idx>> {
    let n = g.node_count();
    let mut part = vec![0 as Idx; n];
    if nparts <= 1 || n == 0 {
        return Some(part);
    }
    let graph = metis::Graph::new(1, nparts as Idx, &g.xadj, &g.adj).ok()?;
    let _lock = METIS_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    graph
        .set_adjwgt(&g.w)
        .set_option(metis::option::Seed(SEED))
        .part_kway(&mut part)
        .ok()?;
    Some(part)
}

fn metis_bisect(g: &Graph, frac_first: f32) -> Option<Vec<Idx>> {
    let n = g.node_count();
    let mut part = vec![0 as Idx; n];
    let tp = [frac_first, 1.0 - frac_first];
    let graph = metis::Graph::new(1, 2, &g.xadj, &g.adj).ok()?;
    let _lock = METIS_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    graph
        .set_adjwgt(&g.w)
        .set_tpwgts(&tp)
        .set_option(metis::option::Seed(SEED))
        .part_recursive(&mut part)
        .ok()?;
    Some(part)
}

/// 63-bit Morton code of a point in the box `[lo, lo + 1/inv]`.
pub(crate) fn morton(p: [f32; 3], lo: [f32; 3], inv: [f32; 3]) -> u64 {
    fn spread(mut x: u64) -> u64 {
        x &= 0x1f_ffff;
        x = (x | x << 32) & 0x1f00000000ffff;
        x = (x | x << 16) & 0x1f0000ff0000ff;
        x = (x | x << 8) & 0x100f00f00f00f00f;
        x = (x | x << 4) & 0x10c30c30c30c30c3;
        x = (x | x << 2) & 0x1249249249249249;
        x
    }
    let mut c = 0u64;
    for k in 0..3 {
        let t = ((p[k] - lo[k]) * inv[k]).clamp(0.0, 1.0);
        let t = if t.is_finite() {
            (t * 2097151.0) as u64
        } else {
            0
        };
        c |= spread(t) << k;
    }
    c
}

/// Morton codes of points, normalized to their bounds.
pub(crate) fn morton_codes(points: &[[f32; 3]]) -> Vec<u64> {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let inv = std::array::from_fn(|k| {
        if hi[k] > lo[k] {
            1.0 / (hi[k] - lo[k])
        } else {
            0.0
        }
    });
    use rayon::prelude::*;
    points.par_iter().map(|p| morton(*p, lo, inv)).collect()
}

/// Chain edges between consecutive items in Morton order (low weight): keeps disconnected parts
/// spatially coherent in the partition.
pub(crate) fn morton_chain_edges(codes: &[u64], weight: i32, edges: &mut Vec<(u32, u32, i32)>) {
    let mut order: Vec<u32> = (0..codes.len() as u32).collect();
    order.sort_unstable_by_key(|&i| (codes[i as usize], i));
    for w in order.windows(2) {
        edges.push((w[0], w[1], weight));
    }
}

/// Partitions the nodes of `g` into parts accepted by `fits`, aiming for `target` nodes per part;
/// parts that do not fit are bisected recursively (METIS, or by Morton order if METIS fails).
/// `max_hint` is the most nodes a part may hold (used for the bisection ratios).
pub(crate) fn partition(
    g: &Graph,
    codes: &[u64],
    target: usize,
    max_hint: usize,
    fits: &dyn Fn(&[u32]) -> bool,
) -> Vec<Vec<u32>> {
    let n = g.node_count();
    let all: Vec<u32> = (0..n as u32).collect();
    let mut out = Vec::new();
    if n == 0 {
        return out;
    }
    if fits(&all) {
        out.push(all);
        return out;
    }
    let nparts = n.div_ceil(target.max(1)).max(2);
    let parts = match metis_kway(g, nparts) {
        Some(p) => {
            let mut parts = vec![Vec::new(); nparts];
            for (i, &p) in p.iter().enumerate() {
                parts[(p as usize).min(nparts - 1)].push(i as u32);
            }
            parts
        }
        None => chunk_by_code(&all, codes, nparts),
    };
    for p in parts {
        if !p.is_empty() {
            bisect(g, codes, p, max_hint, fits, &mut out);
        }
    }
    out
}

fn chunk_by_code(nodes: &[u32], codes: &[u64], nparts: usize) -> Vec<Vec<u32>> {
    let mut order = nodes.to_vec();
    order.sort_unstable_by_key(|&i| (codes[i as usize], i));
    let size = order.len().div_ceil(nparts.max(1)).max(1);
    order
        .chunks(size)
        .map(|c| {
            let mut c = c.to_vec();
            c.sort_unstable();
            c
        })
        .collect()
}

fn bisect(
    g: &Graph,
    codes: &[u64],
    nodes: Vec<u32>,
    max_hint: usize,
    fits: &dyn Fn(&[u32]) -> bool,
    out: &mut Vec<Vec<u32>>,
) {
    if nodes.len() <= 1 || fits(&nodes) {
        out.push(nodes);
        return;
    }
    let k = nodes.len().div_ceil(max_hint.max(1)).max(2);
    let k1 = k / 2;
    let frac = k1 as f32 / k as f32;
    let sub = g.induced(&nodes);
    let mut sides = [Vec::new(), Vec::new()];
    if let Some(part) = metis_bisect(&sub, frac) {
        for (i, &p) in part.iter().enumerate() {
            sides[(p != 0) as usize].push(nodes[i]);
        }
    }
    if sides[0].is_empty() || sides[1].is_empty() {
        let mut order = nodes.clone();
        order.sort_unstable_by_key(|&i| (codes[i as usize], i));
        let cut = ((order.len() as f32 * frac).round() as usize).clamp(1, order.len() - 1);
        let mut a = order[..cut].to_vec();
        let mut b = order[cut..].to_vec();
        a.sort_unstable();
        b.sort_unstable();
        sides = [a, b];
    }
    let [a, b] = sides;
    bisect(g, codes, a, max_hint, fits, out);
    bisect(g, codes, b, max_hint, fits, out);
}

/// Weight of a shared edge in the triangle graph (spatial-neighbour edges weigh 1).
const SHARED_EDGE_WEIGHT: i32 = 32;

/// Splits triangles (global vertex indices; `pid` maps a vertex to its position id) into clusters of
/// at most `max_tris` triangles and `max_verts` unique vertices. Returns triangle indices per cluster.
pub(crate) fn cluster_triangles(
    tris: &[[u32; 3]],
    pid: &[u32],
    positions: &[[f32; 3]],
    max_tris: usize,
    max_verts: usize,
) -> Vec<Vec<u32>> {
    let fits = |part: &[u32]| -> bool {
        if part.len() > max_tris {
            return false;
        }
        if part.len() * 3 <= max_verts {
            return true;
        }
        let mut v: Vec<u32> = part.iter().flat_map(|&t| tris[t as usize]).collect();
        v.sort_unstable();
        v.dedup();
        v.len() <= max_verts
    };
    if tris.is_empty() {
        return Vec::new();
    }
    let all: Vec<u32> = (0..tris.len() as u32).collect();
    if fits(&all) {
        return vec![all];
    }
    // Shared edges (by position id, so attribute seams still connect).
    let mut keyed: Vec<(u64, u32)> = Vec::with_capacity(tris.len() * 3);
    for (t, tri) in tris.iter().enumerate() {
        for e in 0..3 {
            let a = pid[tri[e] as usize];
            let b = pid[tri[(e + 1) % 3] as usize];
            let (a, b) = if a < b { (a, b) } else { (b, a) };
            keyed.push(((a as u64) << 32 | b as u64, t as u32));
        }
    }
    keyed.sort_unstable();
    let mut edges: Vec<(u32, u32, i32)> = Vec::with_capacity(tris.len() * 3);
    let mut i = 0;
    while i < keyed.len() {
        let mut j = i + 1;
        while j < keyed.len() && keyed[j].0 == keyed[i].0 {
            j += 1;
        }
        let run = &keyed[i..j];
        if run.len() <= 8 {
            for x in 0..run.len() {
                for y in x + 1..run.len() {
                    edges.push((run[x].1, run[y].1, SHARED_EDGE_WEIGHT));
                }
            }
        } else {
            for w in run.windows(2) {
                edges.push((w[0].1, w[1].1, SHARED_EDGE_WEIGHT));
            }
        }
        i = j;
    }
    let centroids: Vec<[f32; 3]> = tris
        .iter()
        .map(|t| {
            let (a, b, c) = (
                positions[t[0] as usize],
                positions[t[1] as usize],
                positions[t[2] as usize],
            );
            std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0)
        })
        .collect();
    let codes = morton_codes(&centroids);
    morton_chain_edges(&codes, 1, &mut edges);
    let g = Graph::from_edges(tris.len(), &edges);
    let target = max_tris - max_tris / 16;
    partition(&g, &codes, target.max(1), max_tris, &fits)
}
