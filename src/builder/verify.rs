//! Checks a [`BuiltMesh`]: structure, the DAG invariants of DESIGN.md, and the cut on many views
//! (watertight, no overlap, tau = 0 gives exactly the level-0 triangles, BVH cut = brute cut).

use std::collections::HashMap;
use std::fmt;

use glam::Vec3;

use super::cut::{cut_brute, cut_bvh, proj_scale};
use super::{BVH_FLAG_LEAF, BuiltMesh, NO_GROUP, Sphere};
use crate::shared::{MAX_CLUSTER_TRIANGLES, MAX_CLUSTER_VERTICES};

/// Options of [`verify`].
#[derive(Clone, Debug, PartialEq)]
pub struct VerifyOptions {
    /// Random views for the cut test (0: invariants only).
    pub views: usize,
    /// Seed of the views.
    pub seed: u64,
    /// Most violation lines kept in the report (all are counted).
    pub max_messages: usize,
}

impl Default for VerifyOptions {
    fn default() -> Self {
        Self {
            views: 64,
            seed: 1,
            max_messages: 40,
        }
    }
}

/// What [`verify`] found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VerifyReport {
    /// Readable violations (at most `max_messages`).
    pub violations: Vec<String>,
    /// Number of violations (all of them).
    pub violation_count: usize,
    /// Views whose cut was tested.
    pub views_tested: usize,
    /// Smallest and largest cut (triangles) over the tested views.
    pub cut_triangles_min: usize,
    pub cut_triangles_max: usize,
    /// Cut edges accepted as simplified open borders (both ends on the input's open border).
    pub border_edges_accepted: usize,
    /// Simple open-border loops of the input, on which the cut's border chains are checked
    /// (each must go around its loop exactly once, forward).
    pub border_loops: usize,
}

impl VerifyReport {
    /// True when nothing was violated.
    pub fn ok(&self) -> bool {
        self.violation_count == 0
    }
}

impl fmt::Display for VerifyReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} ({} violations; {} views, cut {}..{} triangles, {} simplified border edges, {} border loops checked)",
            if self.ok() { "OK" } else { "FAILED" },
            self.violation_count,
            self.views_tested,
            self.cut_triangles_min,
            self.cut_triangles_max,
            self.border_edges_accepted,
            self.border_loops
        )?;
        for v in &self.violations {
            writeln!(f, "  - {v}")?;
        }
        if self.violation_count > self.violations.len() {
            writeln!(
                f,
                "  ... and {} more",
                self.violation_count - self.violations.len()
            )?;
        }
        Ok(())
    }
}

struct Sink<'a> {
    r: &'a mut VerifyReport,
    max: usize,
}

impl Sink<'_> {
    fn add(&mut self, msg: String) {
        self.r.violation_count += 1;
        if self.r.violations.len() < self.max {
            self.r.violations.push(msg);
        }
    }
}

fn contains(outer: &Sphere, inner: &Sphere) -> bool {
    let d = ((outer[0] as f64 - inner[0] as f64).powi(2)
        + (outer[1] as f64 - inner[1] as f64).powi(2)
        + (outer[2] as f64 - inner[2] as f64).powi(2))
    .sqrt();
    d + inner[3] as f64 <= outer[3] as f64
}

fn same_sphere(a: &Sphere, b: &Sphere) -> bool {
    a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// SplitMix64: small deterministic generator for views.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e3779b97f4a7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Checks structure first; the DAG and cut checks run only when the structure is sound (so that
/// nothing indexes out of range).
pub fn verify(m: &BuiltMesh, opts: &VerifyOptions) -> VerifyReport {
    let mut report = VerifyReport::default();
    let mut s = Sink {
        r: &mut report,
        max: opts.max_messages,
    };
    if !check_structure(m, &mut s) {
        return report;
    }
    let tris: Vec<Vec<[u32; 3]>> = (0..m.clusters.len())
        .map(|c| m.cluster_triangles(c))
        .collect();
    check_dag(m, &mut s);
    if opts.views > 0 {
        check_cuts(m, &tris, opts, &mut s);
    }
    report
}

/// Structural problems of `m` (references out of range, limits): what the file loader rejects.
pub fn structure_errors(m: &BuiltMesh) -> Vec<String> {
    let mut report = VerifyReport::default();
    let mut s = Sink {
        r: &mut report,
        max: 8,
    };
    check_structure(m, &mut s);
    report.violations
}

fn check_structure(m: &BuiltMesh, s: &mut Sink) -> bool {
    let before = s.r.violation_count;
    let nv = m.vertices.len() as u64;
    if m.clusters.is_empty() {
        s.add("no clusters".into());
        return false;
    }
    if m.root as usize >= m.clusters.len() {
        s.add(format!(
            "root {} out of range ({} clusters)",
            m.root,
            m.clusters.len()
        ));
    }
    if !m.vertex_materials.is_empty() && m.vertex_materials.len() != m.vertices.len() {
        s.add(format!(
            "{} vertex materials for {} vertices",
            m.vertex_materials.len(),
            m.vertices.len()
        ));
    }
    for (ci, c) in m.clusters.iter().enumerate() {
        let (vc, tc) = (c.vertex_count(), c.triangle_count());
        if tc == 0 || tc > MAX_CLUSTER_TRIANGLES || vc == 0 || vc > MAX_CLUSTER_VERTICES {
            s.add(format!(
                "cluster {ci}: {tc} triangles / {vc} vertices out of limits"
            ));
            continue;
        }
        if c.group as usize >= m.groups.len() {
            s.add(format!("cluster {ci}: group {} out of range", c.group));
        }
        if c.creator != NO_GROUP && c.creator as usize >= m.groups.len() {
            s.add(format!(
                "cluster {ci}: creator group {} out of range",
                c.creator
            ));
        }
        let ro = c.vertex_ref_offset as u64;
        if ro + c.vertex_ref_words() as u64 > m.vertex_refs.len() as u64 {
            s.add(format!("cluster {ci}: vertex references out of range"));
            continue;
        }
        let to = c.triangle_offset as u64;
        let tbytes = super::packed_triangle_bytes(vc, tc) as u64;
        if !to.is_multiple_of(4) || to + tbytes > m.triangles.len() as u64 {
            s.add(format!(
                "cluster {ci}: triangles out of range or misaligned"
            ));
            continue;
        }
        for i in 0..vc {
            let v = if c.flags() & super::CLUSTER_FLAG_REFS_U32 != 0 {
                m.vertex_refs[(ro + i as u64) as usize] as u64
            } else {
                let w = m.vertex_refs[(ro + i as u64 / 2) as usize];
                c.vertex_base as u64 + ((w >> (16 * (i & 1))) & 0xffff) as u64
            };
            if v >= nv {
                s.add(format!(
                    "cluster {ci}: vertex reference {i} = {v} out of range ({nv} vertices)"
                ));
                break;
            }
        }
        let bytes = &m.triangles[to as usize..(to + tbytes) as usize];
        let bits = super::index_bits(vc);
        if let Some(t) = (0..3 * tc as usize)
            .map(|k| super::unpack_index(bytes, bits, k).unwrap_or(u32::MAX))
            .find(|&l| l >= vc)
        {
            s.add(format!(
                "cluster {ci}: local index {t} >= vertex count {vc}"
            ));
        }
    }
    for (gi, g) in m.groups.iter().enumerate() {
        let end = g.first_cluster as u64 + g.cluster_count as u64;
        if g.cluster_count == 0 || end > m.clusters.len() as u64 {
            s.add(format!(
                "group {gi}: member range {}+{} invalid",
                g.first_cluster, g.cluster_count
            ));
            continue;
        }
        for ci in g.first_cluster..end as u32 {
            if m.clusters[ci as usize].group != gi as u32 {
                s.add(format!(
                    "group {gi}: member {ci} names group {}",
                    m.clusters[ci as usize].group
                ));
            }
        }
    }
    for (ni, n) in m.bvh.iter().enumerate() {
        let lim = if n.flags & BVH_FLAG_LEAF != 0 {
            m.groups.len()
        } else {
            m.bvh.len()
        };
        if n.first as u64 + n.count as u64 > lim as u64 {
            s.add(format!(
                "BVH node {ni}: range {}+{} out of range",
                n.first, n.count
            ));
        }
    }
    s.r.violation_count == before
}

fn check_dag(m: &BuiltMesh, s: &mut Sink) {
    let root = &m.clusters[m.root as usize];
    if root.parent_error != f32::INFINITY {
        s.add(format!(
            "root cluster {}: parent error {} is not infinite",
            m.root, root.parent_error
        ));
    }
    let mut children: Vec<Vec<u32>> = vec![Vec::new(); m.groups.len()];
    for (ci, c) in m.clusters.iter().enumerate() {
        let g = &m.groups[c.group as usize];
        if c.parent_error.to_bits() != g.error.to_bits()
            || !same_sphere(&c.parent_sphere, &g.lod_sphere)
        {
            s.add(format!(
                "cluster {ci}: parent pair differs from its group {}'s",
                c.group
            ));
        }
        if c.creator == NO_GROUP {
            if c.self_error != 0.0 || c.level != 0 {
                s.add(format!(
                    "cluster {ci}: level-0 cluster with self error {} / level {}",
                    c.self_error, c.level
                ));
            }
        } else {
            let cg = &m.groups[c.creator as usize];
            children[c.creator as usize].push(ci as u32);
            if c.self_error.to_bits() != cg.error.to_bits()
                || !same_sphere(&c.self_sphere, &cg.lod_sphere)
            {
                s.add(format!(
                    "cluster {ci}: self pair differs from its creator group {}'s",
                    c.creator
                ));
            }
            if cg.iteration == u32::MAX || c.level != cg.iteration + 1 {
                s.add(format!(
                    "cluster {ci}: level {} but creator iteration {}",
                    c.level, cg.iteration
                ));
            }
        }
        if c.self_error.partial_cmp(&c.parent_error) != Some(std::cmp::Ordering::Less)
            && c.self_error != c.parent_error
        {
            s.add(format!(
                "cluster {ci}: self error {} > parent error {}",
                c.self_error, c.parent_error
            ));
        }
        if !contains(&c.parent_sphere, &c.self_sphere) {
            s.add(format!(
                "cluster {ci}: parent sphere {:?} does not contain self sphere {:?}",
                c.parent_sphere, c.self_sphere
            ));
        }
    }
    for (gi, ch) in children.iter().enumerate() {
        let is_root_group = m.clusters[m.root as usize].group == gi as u32;
        if ch.is_empty() != is_root_group {
            s.add(format!(
                "group {gi}: {} clusters produced (root group: {is_root_group})",
                ch.len()
            ));
        }
    }
    // Reachability from the root, down through creator groups.
    let mut seen = vec![false; m.clusters.len()];
    let mut gseen = vec![false; m.groups.len()];
    let mut stack = vec![m.root];
    seen[m.root as usize] = true;
    while let Some(c) = stack.pop() {
        let cr = m.clusters[c as usize].creator;
        if cr == NO_GROUP || std::mem::replace(&mut gseen[cr as usize], true) {
            continue;
        }
        let g = &m.groups[cr as usize];
        for mi in g.first_cluster..g.first_cluster + g.cluster_count {
            if !std::mem::replace(&mut seen[mi as usize], true) {
                stack.push(mi);
            }
        }
    }
    let unreached = seen.iter().filter(|x| !**x).count();
    if unreached > 0 {
        s.add(format!(
            "{unreached} clusters not reachable from the root {}",
            m.root
        ));
    }
    // BVH: every group in exactly one leaf.
    let mut refs = vec![0u32; m.groups.len()];
    let mut stack = vec![0u32];
    let mut visits = 0;
    while let Some(n) = stack.pop() {
        visits += 1;
        if visits > m.bvh.len() {
            s.add("BVH has a cycle".into());
            break;
        }
        let node = &m.bvh[n as usize];
        for i in node.first..node.first + node.count {
            if node.flags & BVH_FLAG_LEAF != 0 {
                refs[i as usize] += 1;
            } else {
                stack.push(i);
            }
        }
    }
    if visits != m.bvh.len() {
        s.add(format!(
            "BVH: {visits} of {} nodes reachable from node 0",
            m.bvh.len()
        ));
    }
    for (ni, n) in m.bvh.iter().enumerate() {
        let leaf = n.flags & BVH_FLAG_LEAF != 0;
        let max = if leaf {
            super::bvh::LEAF_GROUPS
        } else {
            super::bvh::FANOUT
        };
        if n.count == 0 || n.count as usize > max {
            s.add(format!("BVH node {ni}: {} children (1..={max})", n.count));
            continue;
        }
        // Children (nodes or groups) must lie inside the node: box, LOD sphere, error.
        for i in n.first..n.first + n.count {
            let (lo, hi, sphere, err) = if leaf {
                let g = &m.groups[i as usize];
                (g.bounds_min, g.bounds_max, g.lod_sphere, g.error)
            } else {
                let c = &m.bvh[i as usize];
                (c.bounds_min, c.bounds_max, c.lod_sphere, c.max_parent_error)
            };
            let inside = (0..3).all(|k| n.bounds_min[k] <= lo[k] && hi[k] <= n.bounds_max[k]);
            if !inside
                || !contains(&n.lod_sphere, &sphere)
                || err.partial_cmp(&n.max_parent_error) == Some(std::cmp::Ordering::Greater)
                || err.is_nan()
            {
                s.add(format!(
                    "BVH node {ni}: child {i} not enclosed (box {inside}, sphere {}, error {err} vs {})",
                    contains(&n.lod_sphere, &sphere),
                    n.max_parent_error
                ));
            }
        }
    }
    if let Some(g) = refs.iter().position(|&r| r != 1) {
        s.add(format!(
            "BVH: group {g} referenced {} times (and maybe others)",
            refs[g]
        ));
    }
}

fn edge_key(a: u32, b: u32) -> u64 {
    (a as u64) << 32 | b as u64
}

fn canonical(t: [u32; 3]) -> [u32; 3] {
    let r = (0..3).min_by_key(|&i| t[i]).unwrap_or(0);
    [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]
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

fn check_cuts(m: &BuiltMesh, tris: &[Vec<[u32; 3]>], opts: &VerifyOptions, s: &mut Sink) {
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
    let mut loop_of = vec![u32::MAX; np];
    let mut loop_idx = vec![0u32; np];
    let mut loop_len: Vec<u32> = Vec::new();
    for start in 0..np {
        if !border[start] || loop_of[start] != u32::MAX || degree[start] != (1, 1) {
            continue;
        }
        // Walk; the loop is simple if it returns to `start` through degree-(1, 1) points only.
        let mut walk = vec![start as u32];
        let mut cur = next_on_border[start];
        let mut simple = true;
        while cur != start as u32 {
            if cur == u32::MAX
                || degree[cur as usize] != (1, 1)
                || loop_of[cur as usize] != u32::MAX
                || walk.len() > np
            {
                simple = false;
                break;
            }
            walk.push(cur);
            cur = next_on_border[cur as usize];
        }
        if simple {
            let id = loop_len.len() as u32;
            for (i, &v) in walk.iter().enumerate() {
                loop_of[v as usize] = id;
                loop_idx[v as usize] = i as u32;
            }
            loop_len.push(walk.len() as u32);
        }
    }
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

    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for p in &positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let center = Vec3::from_array(std::array::from_fn(|k| (lo[k] + hi[k]) * 0.5));
    let radius = (Vec3::from_array(hi) - Vec3::from_array(lo))
        .length()
        .max(1e-20)
        * 0.5;
    let scale = proj_scale(1080.0, 60f32.to_radians());
    let mut rng = Rng(opts.seed ^ 0x5eed);
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
        let cut = cut_brute(m, cam, scale, tau);
        let what = format!("view {view} (camera {:?}, tau {tau})", cam.to_array());
        match cut_bvh(m, cam, scale, tau) {
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
        if tau == 0.0 {
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
