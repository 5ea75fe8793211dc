//! The first `verify` cut check, kept unchanged as the oracle of the fast one in `verify.rs`
//! (`verify_reference`; tests compare the two reports on good and broken DAGs). It hashes every
//! directed edge of every view's cut, so it is slow on large meshes (tens of seconds at 1 M
//! triangles); do not use it outside tests and comparisons.

use std::collections::HashMap;

use glam::Vec3;

use super::super::cut::{cut_brute, cut_bvh, proj_scale};
use super::super::{BuiltMesh, NO_GROUP};
use super::{Rng, Sink, canonical, simple_border_loops, view_bounds, view_name, view_residency};

fn edge_key(a: u32, b: u32) -> u64 {
    (a as u64) << 32 | b as u64
}

struct Uf(Vec<u32>);
impl Uf {
    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let p = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = p;
            x = p;
        }
        x
    }
}

pub(super) fn check_cuts(
    m: &BuiltMesh,
    tris: &[Vec<[u32; 3]>],
    opts: &super::VerifyOptions,
    s: &mut Sink,
) {
    // Position ids: equal decoded positions are one point.
    let positions = m.positions();
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let pid: Vec<u32> = positions
        .iter()
        .map(|p| {
            let n = ids.len() as u32;
            *ids.entry([p[0].to_bits(), p[1].to_bits(), p[2].to_bits()])
                .or_insert(n)
        })
        .collect();
    let ptri = |t: &[u32; 3]| [pid[t[0] as usize], pid[t[1] as usize], pid[t[2] as usize]];
    // Level 0: triangles and directed edge counts.
    let mut orig_edges: HashMap<u64, u32> = HashMap::new();
    let mut orig_tris: Vec<[u32; 3]> = Vec::new();
    for (ci, c) in m.clusters.iter().enumerate() {
        if c.level == 0 {
            for t in &tris[ci] {
                let p = ptri(t);
                orig_tris.push(canonical(p));
                for e in 0..3 {
                    *orig_edges
                        .entry(edge_key(p[e], p[(e + 1) % 3]))
                        .or_default() += 1;
                }
            }
        }
    }
    orig_tris.sort_unstable();
    let count =
        |map: &HashMap<u64, u32>, a: u32, b: u32| map.get(&edge_key(a, b)).copied().unwrap_or(0);
    // Open-border points of the input and their border components.
    let mut uf = Uf((0..ids.len() as u32).collect());
    let mut border = vec![false; ids.len()];
    for &k in orig_edges.keys() {
        let (a, b) = ((k >> 32) as u32, k as u32);
        if (count(&orig_edges, a, b), count(&orig_edges, b, a)) != (1, 1) {
            border[a as usize] = true;
            border[b as usize] = true;
            let (ra, rb) = (uf.find(a), uf.find(b));
            uf.0[ra as usize] = rb;
        }
    }
    // Simple border loops of the input: components of open-border edges where every point has
    // exactly one outgoing and one incoming border edge (used once, never in reverse). Each point
    // gets its loop and its index along the loop, so that a cut's border chain can be checked.
    let np = ids.len();
    let mut next_on_border = vec![u32::MAX; np];
    let mut degree = vec![(0u32, 0u32); np];
    for (&k, &c) in &orig_edges {
        let (a, b) = ((k >> 32) as u32, k as u32);
        if c == 1 && count(&orig_edges, b, a) == 0 {
            next_on_border[a as usize] = b;
            degree[a as usize].0 += 1;
            degree[b as usize].1 += 1;
        } else if (c, count(&orig_edges, b, a)) != (1, 1) {
            // Non-manifold or multiply-used border edges: their points are not on simple loops.
            degree[a as usize].0 += 8;
            degree[b as usize].1 += 8;
        }
    }
    let (loop_of, loop_idx, loop_len) = simple_border_loops(&border, &next_on_border, &degree);
    s.r.border_loops = loop_len.len();
    // Parents of each cluster (clusters created by its group), for the path check.
    let mut children: Vec<Vec<u32>> = vec![Vec::new(); m.groups.len()];
    for (ci, c) in m.clusters.iter().enumerate() {
        if c.creator != NO_GROUP {
            children[c.creator as usize].push(ci as u32);
        }
    }
    let mut by_level: Vec<u32> = (0..m.clusters.len() as u32).collect();
    by_level.sort_by_key(|&c| std::cmp::Reverse(m.clusters[c as usize].level));

    let (center, radius) = view_bounds(&positions);
    let scale = proj_scale(1080.0, 60f32.to_radians());
    let mut rng = Rng(opts.seed ^ 0x5eed);
    let needs = super::super::page::group_needs(m);
    s.r.cut_triangles_min = usize::MAX;
    for view in 0..opts.views {
        // Directions uniform on the sphere; distances from inside the mesh to far away.
        let z = rng.unit() * 2.0 - 1.0;
        let phi = rng.unit() * std::f64::consts::TAU;
        let rxy = (1.0 - z * z).max(0.0).sqrt();
        let dir = Vec3::new((rxy * phi.cos()) as f32, (rxy * phi.sin()) as f32, z as f32);
        let dist = radius * 10f32.powf((rng.unit() * 3.5 - 1.5) as f32);
        let cam = center + dir * dist;
        let tau = if view % 8 == 0 {
            0.0
        } else {
            2f32.powf((rng.unit() * 9.0 - 3.0) as f32)
        };
        let res = view_residency(m, &needs, opts.seed, view);
        let res = res.as_deref();
        s.r.residency_views += res.is_some() as usize;
        let cut = cut_brute(m, cam, scale, tau, res);
        let what = view_name(view, cam, tau, res);
        match cut_bvh(m, cam, scale, tau, res) {
            Some(b) if b == cut => {}
            Some(b) => s.add(format!(
                "{what}: BVH cut has {} clusters, brute cut {}",
                b.len(),
                cut.len()
            )),
            None => s.add(format!("{what}: BVH traversal went out of range")),
        }
        // Every leaf-to-root path crosses the cut exactly once.
        let mut drawn = vec![false; m.clusters.len()];
        for &c in &cut {
            drawn[c as usize] = true;
        }
        let mut up = vec![(0u32, 0u32); m.clusters.len()];
        for &c in &by_level {
            let cl = &m.clusters[c as usize];
            let d = drawn[c as usize] as u32;
            up[c as usize] = if c == m.root {
                (d, d)
            } else {
                let ps = &children[cl.group as usize];
                let mn = ps.iter().map(|&p| up[p as usize].0).min().unwrap_or(0);
                let mx = ps.iter().map(|&p| up[p as usize].1).max().unwrap_or(0);
                (d + mn, d + mx)
            };
        }
        let bad = (0..m.clusters.len())
            .filter(|&c| m.clusters[c].level == 0 && up[c] != (1, 1))
            .count();
        if bad > 0 {
            s.add(format!(
                "{what}: {bad} level-0 clusters not covered exactly once by the cut"
            ));
        }
        // Edges.
        let mut edges: HashMap<u64, u32> = HashMap::new();
        let mut cut_tris = Vec::new();
        for &c in &cut {
            for t in &tris[c as usize] {
                let p = ptri(t);
                cut_tris.push(canonical(p));
                for e in 0..3 {
                    *edges.entry(edge_key(p[e], p[(e + 1) % 3])).or_default() += 1;
                }
            }
        }
        s.r.cut_triangles_min = s.r.cut_triangles_min.min(cut_tris.len());
        s.r.cut_triangles_max = s.r.cut_triangles_max.max(cut_tris.len());
        let mut keys: Vec<u64> = edges.keys().copied().collect();
        keys.sort_unstable();
        let (mut cracks, mut overlaps) = (0usize, 0usize);
        let mut example = None;
        for k in keys {
            let (a, b) = ((k >> 32) as u32, k as u32);
            if a > b && edges.contains_key(&edge_key(b, a)) {
                continue; // counted from the other direction
            }
            let (f, r) = (count(&edges, a, b), count(&edges, b, a));
            let (f0, r0) = (count(&orig_edges, a, b), count(&orig_edges, b, a));
            if f == r || (f, r) == (f0, r0) {
                continue;
            }
            if f + r == 1 && border[a as usize] && border[b as usize] && uf.find(a) == uf.find(b) {
                s.r.border_edges_accepted += 1;
                continue;
            }
            if f > 1 || r > 1 {
                overlaps += 1
            } else {
                cracks += 1
            }
            example.get_or_insert((a, b, f, r, f0, r0));
        }
        // Border chains: on each simple input border loop, the cut's edges used once in one
        // direction only must form one chain that goes around the loop exactly once, forward
        // (a simplified border replaces a run of border edges by a chord in the same direction);
        // a crack ending on the border, a backward or overlapping chord breaks this.
        let mut walked = vec![0u64; loop_len.len()];
        let mut out_deg: HashMap<u32, (u32, u32)> = HashMap::new();
        for (&k, &f) in &edges {
            let (a, b) = ((k >> 32) as u32, k as u32);
            let l = loop_of[a as usize];
            if f != 1 || count(&edges, b, a) != 0 || l == u32::MAX || loop_of[b as usize] != l {
                continue;
            }
            let len = loop_len[l as usize];
            let d = (loop_idx[b as usize] + len - loop_idx[a as usize]) % len;
            walked[l as usize] += d as u64;
            out_deg.entry(a).or_default().0 += 1;
            out_deg.entry(b).or_default().1 += 1;
        }
        let bad_loops = walked
            .iter()
            .zip(&loop_len)
            .filter(|&(&w, &len)| w != 0 && w != len as u64)
            .count();
        let bad_points = out_deg.values().filter(|d| **d != (1, 1)).count();
        if bad_loops > 0 || bad_points > 0 {
            s.add(format!(
                "{what}: border chains broken on {bad_loops} of {} input border loops ({bad_points} points without one incoming and one outgoing border edge)",
                loop_len.len()
            ));
        }
        if let Some((a, b, f, r, f0, r0)) = example {
            s.add(format!(
                "{what}: {cracks} unmatched and {overlaps} over-used edges, e.g. {:?} -> {:?} used {f}/{r} times (input: {f0}/{r0})",
                positions[pid.iter().position(|&x| x == a).unwrap_or(0)],
                positions[pid.iter().position(|&x| x == b).unwrap_or(0)]
            ));
        }
        if tau == 0.0 && res.is_none() {
            cut_tris.sort_unstable();
            if cut_tris != orig_tris {
                s.add(format!(
                    "{what}: tau = 0 cut has {} triangles, not the {} input triangles",
                    cut_tris.len(),
                    orig_tris.len()
                ));
            }
        }
        s.r.views_tested += 1;
    }
    if s.r.views_tested == 0 {
        s.r.cut_triangles_min = 0;
    }
}
