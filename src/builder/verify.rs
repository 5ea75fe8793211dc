//! Checks a [`BuiltMesh`]: structure, the DAG invariants of DESIGN.md, and the cut on many views
//! (watertight, no overlap, tau = 0 gives exactly the level-0 triangles, BVH cut = brute cut).

use std::fmt;
use std::sync::{Mutex, OnceLock};

use glam::Vec3;
use rayon::prelude::*;

use super::cut::{cut_brute, cut_bvh, proj_scale};
use super::{BVH_FLAG_LEAF, BuiltMesh, NO_GROUP, Sphere, uf_find};
use crate::shared::{MAX_CLUSTER_LEVEL, MAX_CLUSTER_TRIANGLES, MAX_CLUSTER_VERTICES};

mod reference;

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
    /// Smallest cut (triangles) over the tested views.
    pub cut_triangles_min: usize,
    /// Largest cut (triangles) over the tested views.
    pub cut_triangles_max: usize,
    /// Cut edges accepted as simplified open borders (both ends on the input's open border).
    pub border_edges_accepted: usize,
    /// Simple open-border loops of the input, on which the cut's border chains are checked
    /// (each must go around its loop exactly once, forward).
    pub border_loops: usize,
    /// Views tested under a random closed partial residency of the pages (every fourth view,
    /// [`view_residency`]).
    pub residency_views: usize,
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
            "{} ({} violations; {} views ({} under partial residency), cut {}..{} triangles, {} simplified border edges, {} border loops checked)",
            if self.ok() { "OK" } else { "FAILED" },
            self.violation_count,
            self.views_tested,
            self.residency_views,
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

/// Whether the box `lo..hi` lies inside `outer_lo..outer_hi` (false with a NaN).
fn box_inside(lo: [f32; 3], hi: [f32; 3], outer_lo: [f32; 3], outer_hi: [f32; 3]) -> bool {
    (0..3).all(|k| outer_lo[k] <= lo[k] && hi[k] <= outer_hi[k])
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

/// SplitMix64: small deterministic generator for views (and the builder's unit tests).
pub(crate) struct Rng(pub(crate) u64);
impl Rng {
    pub(crate) fn next(&mut self) -> u64 {
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
    check_dag(m, &mut s);
    if opts.views > 0 {
        check_cuts(m, opts, &mut s);
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

/// [`structure_errors`] of a mesh's head: everything but the pages' content (the vertex,
/// reference and triangle streams may be empty: a `.vgeo` file opened page by page checks each
/// page's content as it reads it).
pub fn head_errors(m: &BuiltMesh) -> Vec<String> {
    let mut report = VerifyReport::default();
    let mut s = Sink {
        r: &mut report,
        max: 8,
    };
    check_structure_of(m, &mut s, false);
    report.violations
}

fn check_structure(m: &BuiltMesh, s: &mut Sink) -> bool {
    check_structure_of(m, s, true)
}

/// The structure checks; with `streams`, also the pages' content (vertex references, local
/// indices, vertex materials).
fn check_structure_of(m: &BuiltMesh, s: &mut Sink, streams: bool) -> bool {
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
    let want = if m.has_material_stream() {
        m.vertices.len()
    } else {
        0
    };
    if streams && m.vertex_materials.len() != want {
        s.add(format!(
            "{} vertex materials for {} vertices",
            m.vertex_materials.len(),
            m.vertices.len()
        ));
    }
    if !check_pages(m, s, streams) {
        return false;
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
        // The GPU reads a cluster's LOD pairs from its groups (its parent pair from its group,
        // its self pair from its creator), so they must be theirs.
        let pair = |sp: &Sphere, e: f32| (sp.map(f32::to_bits), e.to_bits());
        if let Some(g) = m.groups.get(c.group as usize)
            && pair(&c.parent_sphere, c.parent_error) != pair(&g.lod_sphere, g.error)
        {
            s.add(format!("cluster {ci}: parent pair is not its group's"));
        }
        if c.creator == NO_GROUP {
            if c.self_error != 0.0 {
                s.add(format!(
                    "cluster {ci}: level-0 cluster with self error {}",
                    c.self_error
                ));
            }
        } else if let Some(g) = m.groups.get(c.creator as usize)
            && pair(&c.self_sphere, c.self_error) != pair(&g.lod_sphere, g.error)
        {
            s.add(format!(
                "cluster {ci}: self pair is not its creator group's"
            ));
        }
        if c.level > MAX_CLUSTER_LEVEL {
            s.add(format!(
                "cluster {ci}: level {} over {MAX_CLUSTER_LEVEL}",
                c.level
            ));
        }
        let Some(p) = m.pages.get(c.page as usize) else {
            s.add(format!("cluster {ci}: page {} out of range", c.page));
            continue;
        };
        if c.flags() != 0 {
            // Full u32 references exist only inside the builder, before pagination.
            s.add(format!("cluster {ci}: flags {:#x}", c.flags()));
            continue;
        }
        let ro = c.vertex_ref_offset as u64;
        if ro < p.ref_first as u64
            || ro + c.vertex_ref_words() as u64 > p.ref_first as u64 + p.ref_words as u64
        {
            s.add(format!(
                "cluster {ci}: vertex references outside its page {}",
                c.page
            ));
            continue;
        }
        let to = c.triangle_offset as u64;
        let tbytes = super::packed_triangle_bytes(vc, tc) as u64;
        if !to.is_multiple_of(4)
            || to < p.triangle_first as u64
            || to + tbytes > p.triangle_first as u64 + p.triangle_bytes as u64
        {
            s.add(format!(
                "cluster {ci}: triangles misaligned or outside its page {}",
                c.page
            ));
            continue;
        }
        if !streams {
            continue;
        }
        let (pv0, pv1) = (
            p.vertex_first as u64,
            p.vertex_first as u64 + p.vertex_count as u64,
        );
        for i in 0..vc {
            let w = m.vertex_refs[(ro + i as u64 / 2) as usize];
            let v = pv0 + ((w >> (16 * (i & 1))) & 0xffff) as u64;
            if v >= nv || v < pv0 || v >= pv1 {
                s.add(format!(
                    "cluster {ci}: vertex reference {i} = {v} outside its page {} \
                     ({pv0}..{pv1} of {nv} vertices)",
                    c.page
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
    if !m.group_coverage.is_empty() && m.group_coverage.len() != m.groups.len() {
        s.add(format!(
            "{} coverage values for {} groups",
            m.group_coverage.len(),
            m.groups.len()
        ));
    }
    for (gi, g) in m.groups.iter().enumerate() {
        let cov = m.group_coverage_of(gi as u32);
        let bounded = (0.0..=g.error).contains(&cov);
        if !m.group_coverage.is_empty() && !bounded {
            s.add(format!(
                "group {gi}: coverage {cov} not within 0..={} (its error)",
                g.error
            ));
        }
        let end = g.first_cluster as u64 + g.cluster_count as u64;
        if g.cluster_count == 0 || end > m.clusters.len() as u64 {
            s.add(format!(
                "group {gi}: member range {}+{} invalid",
                g.first_cluster, g.cluster_count
            ));
            continue;
        }
        let pages = g.page_first as u64..g.page_first as u64 + g.page_count as u64;
        if g.page_count == 0 || pages.end > m.pages.len() as u64 {
            s.add(format!(
                "group {gi}: page range {}+{} invalid",
                g.page_first, g.page_count
            ));
        }
        for ci in g.first_cluster..end as u32 {
            if !pages.contains(&(m.clusters[ci as usize].page as u64)) {
                s.add(format!(
                    "group {gi}: member {ci} lies in page {}, outside the group's pages",
                    m.clusters[ci as usize].page
                ));
            }
            if m.clusters[ci as usize].group != gi as u32 {
                s.add(format!(
                    "group {gi}: member {ci} names group {}",
                    m.clusters[ci as usize].group
                ));
            }
            // The cull walks the BVH by the groups' boxes (a leaf's box encloses its groups').
            let c = &m.clusters[ci as usize];
            if !box_inside(c.bounds_min, c.bounds_max, g.bounds_min, g.bounds_max) {
                s.add(format!(
                    "group {gi}: member {ci}'s bounds outside the group's box"
                ));
            }
        }
    }
    // instance_cull tests an instance by the BVH root's box: every cluster of every level (the
    // small-instance table's and the root's too, drawn without a walk) must lie inside it.
    match m.bvh.first() {
        None => s.add("no BVH nodes".into()),
        Some(root) => {
            let outside = m
                .clusters
                .iter()
                .filter(|c| {
                    !box_inside(c.bounds_min, c.bounds_max, root.bounds_min, root.bounds_max)
                })
                .count();
            if outside > 0 {
                s.add(format!(
                    "{outside} clusters' bounds outside the BVH root's box"
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

/// The pages cover the vertex, reference and triangle streams in order without gaps, each within
/// [`super::page::PAGE_BYTES`], and the always-resident prefix is a non-empty part of them.
fn check_pages(m: &BuiltMesh, s: &mut Sink, streams: bool) -> bool {
    let before = s.r.violation_count;
    if m.pages.is_empty() || m.resident_pages == 0 || m.resident_pages as usize > m.pages.len() {
        s.add(format!(
            "{} pages, {} always resident",
            m.pages.len(),
            m.resident_pages
        ));
        return false;
    }
    let (mut v, mut r, mut t) = (0u64, 0u64, 0u64);
    for (pi, p) in m.pages.iter().enumerate() {
        if p.vertex_first as u64 != v || p.ref_first as u64 != r || p.triangle_first as u64 != t {
            s.add(format!(
                "page {pi}: streams start at {}/{}/{}, not where page {} ends ({v}/{r}/{t})",
                p.vertex_first,
                p.ref_first,
                p.triangle_first,
                pi as i64 - 1
            ));
            return false;
        }
        v += p.vertex_count as u64;
        r += p.ref_words as u64;
        t += p.triangle_bytes as u64;
        let len = p.bytes as usize;
        if len > super::page::PAGE_BYTES as usize
            || !len.is_multiple_of(4)
            || p.vertex_count > 1 << 16
        {
            s.add(format!(
                "page {pi}: {len} bytes, {} vertices (at most {} in words and 65536)",
                p.vertex_count,
                super::page::PAGE_BYTES
            ));
        }
    }
    if streams
        && (v != m.vertices.len() as u64
            || r != m.vertex_refs.len() as u64
            || t != m.triangles.len() as u64)
    {
        s.add(format!(
            "pages cover {v} vertices, {r} reference words, {t} triangle bytes of {}, {}, {}",
            m.vertices.len(),
            m.vertex_refs.len(),
            m.triangles.len()
        ));
    }
    let mut counts = vec![0u64; m.pages.len()];
    for c in &m.clusters {
        if let Some(n) = counts.get_mut(c.page as usize) {
            *n += 1;
        }
    }
    for (pi, (p, &n)) in m.pages.iter().zip(&counts).enumerate() {
        if p.cluster_count as u64 != n {
            s.add(format!(
                "page {pi}: says it holds {} clusters, {n} name it",
                p.cluster_count
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
        // The SW/HW split's measure (builder::size): exactly what its triangles give.
        let tris = m.cluster_triangles(ci);
        let code = super::size::cluster_size_code(
            tris.iter().map(|t| t.map(|v| m.position(v))),
            c.bounds_min,
            c.bounds_max,
        );
        if code != c.size_code() {
            s.add(format!(
                "cluster {ci}: size code {} but its triangles give {code}",
                c.size_code()
            ));
        }
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
            // The coverage part grows towards the root as the error does, so a small instance's
            // weighted errors stay monotonic (its cut crack-free).
            let (own, up) = (m.group_coverage_of(c.creator), m.group_coverage_of(c.group));
            if own
                .partial_cmp(&up)
                .is_none_or(|o| o == std::cmp::Ordering::Greater)
            {
                s.add(format!(
                    "cluster {ci}: coverage {own} of its creator group {} above {up} of its group {}",
                    c.creator, c.group
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
            let (lo, hi, sphere, err, cov) = if leaf {
                let g = &m.groups[i as usize];
                let cov = m.group_coverage_of(i);
                (g.bounds_min, g.bounds_max, g.lod_sphere, g.error, cov)
            } else {
                let c = &m.bvh[i as usize];
                let cov = c.max_parent_coverage;
                (
                    c.bounds_min,
                    c.bounds_max,
                    c.lod_sphere,
                    c.max_parent_error,
                    cov,
                )
            };
            let inside = box_inside(lo, hi, n.bounds_min, n.bounds_max);
            let above = |a: f32, b: f32| a.partial_cmp(&b) == Some(std::cmp::Ordering::Greater);
            if !inside
                || !contains(&n.lod_sphere, &sphere)
                || above(err, n.max_parent_error)
                || err.is_nan()
                || above(cov, n.max_parent_coverage)
                || cov.is_nan()
            {
                s.add(format!(
                    "BVH node {ni}: child {i} not enclosed (box {inside}, sphere {}, error {err} vs {}, coverage {cov} vs {})",
                    contains(&n.lod_sphere, &sphere),
                    n.max_parent_error,
                    n.max_parent_coverage
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

/// The triangle with its smallest index first (same orientation).
fn canonical(t: [u32; 3]) -> [u32; 3] {
    let r = (0..3).min_by_key(|&i| t[i]).unwrap_or(0);
    [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]
}

/// The oracle: the same checks as [`verify`] with the first, straightforward cut check (every
/// directed edge of every view's cut hashed; slow on large meshes). Its report must equal
/// [`verify`]'s on every mesh, good or broken; the tests compare them.
#[doc(hidden)]
pub fn verify_reference(m: &BuiltMesh, opts: &VerifyOptions) -> VerifyReport {
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
        reference::check_cuts(m, &tris, opts, &mut s);
    }
    report
}

/// Center and radius of the decoded positions' bounding box, which the views circle.
pub(super) fn view_bounds(positions: &[[f32; 3]]) -> (Vec3, f32) {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for p in positions {
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
    (center, radius)
}

/// Simple border loops: chains of points that each have exactly one outgoing and one incoming
/// border edge (`degree`), following `next_on_border`. Returns each point's loop (`u32::MAX`:
/// none), its index along the loop, and each loop's length.
pub(super) fn simple_border_loops(
    border: &[bool],
    next_on_border: &[u32],
    degree: &[(u32, u32)],
) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    let np = border.len();
    let mut loop_of = vec![u32::MAX; np];
    let mut loop_idx = vec![0u32; np];
    let mut loop_len: Vec<u32> = Vec::new();
    let mut walk = Vec::new();
    for start in 0..np {
        if !border[start] || loop_of[start] != u32::MAX || degree[start] != (1, 1) {
            continue;
        }
        // The loop is simple if it returns to `start` through degree-(1, 1) points only.
        walk.clear();
        walk.push(start as u32);
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
    (loop_of, loop_idx, loop_len)
}

/// The page residency of view `view` of the cut test: every fourth view (`view % 4 == 3`) a
/// random closed set (each page resident with a probability drawn per view, then closed by
/// [`super::page::close_residency`]), the others `None` (every page).
pub(super) fn view_residency(
    m: &BuiltMesh,
    needs: &[Vec<u32>],
    seed: u64,
    view: usize,
) -> Option<Vec<bool>> {
    if view % 4 != 3 {
        return None;
    }
    let mut rng = Rng(seed ^ 0x7e51_de9c ^ (view as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
    let share = rng.unit();
    let mut res: Vec<bool> = (0..m.pages.len()).map(|_| rng.unit() < share).collect();
    super::page::close_residency(m, needs, &mut res);
    Some(res)
}

/// The views of the cut test, (camera, tau): directions uniform on the sphere, distances from
/// inside the mesh to far away, every 8th view at tau = 0 (the reference draws the same sequence).
fn draw_views(center: Vec3, radius: f32, opts: &VerifyOptions) -> Vec<(Vec3, f32)> {
    let mut rng = Rng(opts.seed ^ 0x5eed);
    (0..opts.views)
        .map(|view| {
            let z = rng.unit() * 2.0 - 1.0;
            let phi = rng.unit() * std::f64::consts::TAU;
            let rxy = (1.0 - z * z).max(0.0).sqrt();
            let dir = Vec3::new((rxy * phi.cos()) as f32, (rxy * phi.sin()) as f32, z as f32);
            let dist = radius * 10f32.powf((rng.unit() * 3.5 - 1.5) as f32);
            let tau = if view % 8 == 0 {
                0.0
            } else {
                2f32.powf((rng.unit() * 9.0 - 3.0) as f32)
            };
            (center + dir * dist, tau)
        })
        .collect()
}

/// An edge between position ids `x <= y` that is counted per view: one that occurs in more than
/// one cluster, or not exactly once each way in its only cluster. (An edge used once each way
/// inside a single cluster and nowhere else is matched in every cut that draws the cluster, and
/// absent from every other; it can never be a crack, an overlap or a border edge.) `f0` / `r0`: its
/// uses x -> y / y -> x in the input (level 0). An edge with `x == y` (a zero-area triangle's)
/// counts each use both ways, as the reference's single self key does.
#[derive(Clone, Copy, Debug)]
struct Edge {
    x: u32,
    y: u32,
    f0: u32,
    r0: u32,
}

/// A cluster's uses of a counted edge: `f` times x -> y, `r` times y -> x.
#[derive(Clone, Copy, Debug, Default)]
struct Use {
    edge: u32,
    f: u16,
    r: u16,
}

/// A cluster's distinct edges with their use counts (x <= y; see [`Edge`]).
#[derive(Clone, Copy, Debug, Default)]
struct LocalEdge {
    x: u32,
    y: u32,
    f: u16,
    r: u16,
}

/// Everything about the cut test that does not depend on the view, computed once.
struct Prep {
    /// Position of each position id (its first vertex's).
    id_pos: Vec<[f32; 3]>,
    /// Triangles of cluster `c` (as position ids): `tris[tri_off[c]..tri_off[c + 1]]`.
    tri_off: Vec<usize>,
    tris: Vec<[u32; 3]>,
    /// Level-0 clusters, ascending, and their triangle count.
    level0: Vec<u32>,
    level0_triangles: usize,
    /// Counted edges, and each cluster's uses of them: `uses[use_off[c]..use_off[c + 1]]`.
    edges: Vec<Edge>,
    use_off: Vec<usize>,
    uses: Vec<Use>,
    /// Per position id: on the input's open border, its border component.
    border: Vec<bool>,
    comp: Vec<u32>,
    /// Per position id: simple border loop and index along it (`u32::MAX`: none), and its index
    /// among the loop points (for per-view degree counts).
    loop_of: Vec<u32>,
    loop_idx: Vec<u32>,
    loop_point: Vec<u32>,
    loop_len: Vec<u32>,
    /// Clusters created by each group (its members' parents), and clusters by level, coarsest first.
    children: Vec<Vec<u32>>,
    by_level: Vec<u32>,
    /// The input's triangles (canonical, sorted), only built if a tau = 0 cut is not exactly the
    /// level-0 clusters.
    orig_tris: OnceLock<Vec<[u32; 3]>>,
}

/// Position ids: equal decoded positions (bit for bit) are one point, numbered in the order of
/// their first vertex (the reference's numbering, on which its reports' choice of example edge
/// depends). Returns each vertex's id and each id's position.
fn position_ids(positions: &[[f32; 3]]) -> (Vec<u32>, Vec<[f32; 3]>) {
    let n = positions.len();
    let mut keys: Vec<[u32; 4]> = positions
        .par_iter()
        .enumerate()
        .map(|(i, p)| [p[0].to_bits(), p[1].to_bits(), p[2].to_bits(), i as u32])
        .collect();
    keys.par_sort_unstable();
    // Each vertex's representative: the first vertex with its position.
    let mut rep = vec![0u32; n];
    let mut i = 0;
    while i < n {
        let r = keys[i][3];
        let mut j = i;
        while j < n && keys[j][..3] == keys[i][..3] {
            rep[keys[j][3] as usize] = r;
            j += 1;
        }
        i = j;
    }
    drop(keys);
    let mut id_of_rep = vec![u32::MAX; n];
    let mut id_pos = Vec::new();
    for v in 0..n {
        if rep[v] == v as u32 {
            id_of_rep[v] = id_pos.len() as u32;
            id_pos.push(positions[v]);
        }
    }
    let pid = rep.iter().map(|&r| id_of_rep[r as usize]).collect();
    (pid, id_pos)
}

/// The distinct edges of one cluster's triangles with their use counts, sorted by (x, y).
fn local_edges(tris: &[[u32; 3]]) -> Vec<LocalEdge> {
    let mut dir: Vec<(u64, bool)> = Vec::with_capacity(tris.len() * 3);
    for t in tris {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            dir.push(((a.min(b) as u64) << 32 | a.max(b) as u64, a > b));
        }
    }
    dir.sort_unstable();
    let mut out: Vec<LocalEdge> = Vec::with_capacity(dir.len());
    for (k, back) in dir {
        let (x, y) = ((k >> 32) as u32, k as u32);
        if out.last().is_none_or(|l| (l.x, l.y) != (x, y)) {
            out.push(LocalEdge { x, y, f: 0, r: 0 });
        }
        let l = out.last_mut().expect("pushed");
        if x == y {
            l.f += 1;
            l.r += 1;
        } else if back {
            l.r += 1;
        } else {
            l.f += 1;
        }
    }
    out
}

impl Prep {
    fn new(m: &BuiltMesh, positions: &[[f32; 3]]) -> Self {
        let nc = m.clusters.len();
        let (pid, id_pos) = position_ids(positions);
        let np = id_pos.len();
        let per_cluster: Vec<Vec<[u32; 3]>> = (0..nc)
            .into_par_iter()
            .map(|c| {
                let mut t = m.cluster_triangles(c);
                for v in t.iter_mut().flatten() {
                    *v = pid[*v as usize];
                }
                t
            })
            .collect();
        drop(pid);
        let mut tri_off = Vec::with_capacity(nc + 1);
        tri_off.push(0);
        for t in &per_cluster {
            tri_off.push(tri_off.last().copied().unwrap_or(0) + t.len());
        }
        let tris = per_cluster.concat();
        drop(per_cluster);
        let level0: Vec<u32> = (0..nc as u32)
            .filter(|&c| m.clusters[c as usize].level == 0)
            .collect();
        let level0_triangles = level0
            .iter()
            .map(|&c| tri_off[c as usize + 1] - tri_off[c as usize])
            .sum();

        // Every cluster's distinct edges, bucketed by their smaller end (a counting sort), then
        // sorted by the other end within each bucket (stably: clusters stay in order).
        let local: Vec<Vec<LocalEdge>> = (0..nc)
            .into_par_iter()
            .map(|c| local_edges(&tris[tri_off[c]..tri_off[c + 1]]))
            .collect();
        let mut bucket_off = vec![0usize; np + 1];
        for l in &local {
            for e in l {
                bucket_off[e.x as usize + 1] += 1;
            }
        }
        for x in 0..np {
            bucket_off[x + 1] += bucket_off[x];
        }
        let mut entries = vec![(0u32, 0u32, 0u16, 0u16); bucket_off[np]];
        let mut cursor = bucket_off.clone();
        for (c, l) in local.iter().enumerate() {
            for e in l {
                let at = &mut cursor[e.x as usize];
                entries[*at] = (e.y, c as u32, e.f, e.r);
                *at += 1;
            }
        }
        drop(local);
        drop(cursor);
        {
            // Sort the buckets in parallel, in runs of whole buckets.
            let runs = 256.min(np.max(1));
            let mut slices = Vec::with_capacity(runs);
            let mut rest: &mut [(u32, u32, u16, u16)] = &mut entries;
            for k in 0..runs {
                let (lo, hi) = (k * np / runs, (k + 1) * np / runs);
                let (a, b) = rest.split_at_mut(bucket_off[hi] - bucket_off[lo]);
                slices.push((lo, a));
                rest = b;
            }
            slices.into_par_iter().for_each(|(lo, s)| {
                let base = bucket_off[lo];
                let mut x = lo;
                while bucket_off[x] - base < s.len() {
                    s[bucket_off[x] - base..bucket_off[x + 1] - base].sort_by_key(|e| e.0);
                    x += 1;
                }
            });
        }

        // Counted edges and each cluster's uses of them.
        let mut edges = Vec::new();
        let mut uses_by_edge: Vec<(u32, Use)> = Vec::new();
        for x in 0..np {
            let b = &entries[bucket_off[x]..bucket_off[x + 1]];
            let mut i = 0;
            while i < b.len() {
                let y = b[i].0;
                let mut j = i;
                let (mut f0, mut r0) = (0u32, 0u32);
                while j < b.len() && b[j].0 == y {
                    if m.clusters[b[j].1 as usize].level == 0 {
                        f0 += b[j].2 as u32;
                        r0 += b[j].3 as u32;
                    }
                    j += 1;
                }
                let run = &b[i..j];
                i = j;
                if run.len() == 1 && (run[0].2, run[0].3) == (1, 1) {
                    continue;
                }
                let edge = edges.len() as u32;
                edges.push(Edge {
                    x: x as u32,
                    y,
                    f0,
                    r0,
                });
                for &(_, c, f, r) in run {
                    uses_by_edge.push((c, Use { edge, f, r }));
                }
            }
        }
        drop(entries);
        let mut use_off = vec![0usize; nc + 1];
        for (c, _) in &uses_by_edge {
            use_off[*c as usize + 1] += 1;
        }
        for c in 0..nc {
            use_off[c + 1] += use_off[c];
        }
        let mut uses = vec![Use::default(); uses_by_edge.len()];
        let mut cursor = use_off.clone();
        for (c, u) in uses_by_edge {
            uses[cursor[c as usize]] = u;
            cursor[c as usize] += 1;
        }

        // Open-border points of the input and their border components: ends of input edges not
        // used exactly once each way.
        let mut uf: Vec<u32> = (0..np as u32).collect();
        let mut border = vec![false; np];
        let mut next_on_border = vec![u32::MAX; np];
        let mut degree = vec![(0u32, 0u32); np];
        for e in &edges {
            if e.f0 + e.r0 == 0 || (e.f0, e.r0) == (1, 1) {
                continue;
            }
            border[e.x as usize] = true;
            border[e.y as usize] = true;
            let (ra, rb) = (uf_find(&mut uf, e.x), uf_find(&mut uf, e.y));
            uf[ra as usize] = rb;
            // Border edges used once, one way only, chain into loops; other uses (non-manifold,
            // multiply used) keep their points off the simple loops.
            let dirs = if e.x == e.y {
                &[(e.x, e.y, e.f0, e.r0)][..]
            } else {
                &[(e.x, e.y, e.f0, e.r0), (e.y, e.x, e.r0, e.f0)][..]
            };
            for &(a, b, c, rev) in dirs {
                if c == 0 {
                    continue;
                }
                if c == 1 && rev == 0 {
                    next_on_border[a as usize] = b;
                    degree[a as usize].0 += 1;
                    degree[b as usize].1 += 1;
                } else {
                    degree[a as usize].0 += 8;
                    degree[b as usize].1 += 8;
                }
            }
        }
        let comp: Vec<u32> = (0..np as u32).map(|p| uf_find(&mut uf, p)).collect();
        drop(uf);
        // Simple border loops: every point with exactly one outgoing and one incoming border
        // edge; each point gets its loop and its index along it.
        let (loop_of, loop_idx, loop_len) = simple_border_loops(&border, &next_on_border, &degree);
        let mut loop_point = vec![u32::MAX; np];
        let mut n = 0;
        for (p, l) in loop_of.iter().enumerate() {
            if *l != u32::MAX {
                loop_point[p] = n;
                n += 1;
            }
        }

        let mut children: Vec<Vec<u32>> = vec![Vec::new(); m.groups.len()];
        for (ci, c) in m.clusters.iter().enumerate() {
            if c.creator != NO_GROUP {
                children[c.creator as usize].push(ci as u32);
            }
        }
        let mut by_level: Vec<u32> = (0..nc as u32).collect();
        by_level.sort_by_key(|&c| std::cmp::Reverse(m.clusters[c as usize].level));
        Prep {
            id_pos,
            tri_off,
            tris,
            level0,
            level0_triangles,
            edges,
            use_off,
            uses,
            border,
            comp,
            loop_of,
            loop_idx,
            loop_point,
            loop_len,
            children,
            by_level,
            orig_tris: OnceLock::new(),
        }
    }

    fn cluster_tris(&self, c: u32) -> &[[u32; 3]] {
        &self.tris[self.tri_off[c as usize]..self.tri_off[c as usize + 1]]
    }

    /// The triangles of `clusters`, canonical and sorted.
    fn sorted_tris(&self, clusters: &[u32]) -> Vec<[u32; 3]> {
        let mut t: Vec<[u32; 3]> = clusters
            .iter()
            .flat_map(|&c| self.cluster_tris(c).iter().map(|&t| canonical(t)))
            .collect();
        t.par_sort_unstable();
        t
    }
}

/// Per-thread buffers of the view checks, reused from view to view (left cleared).
struct Scratch {
    /// Uses of each counted edge in this view's cut, x -> y and y -> x.
    count: Vec<[u32; 2]>,
    touched: Vec<u32>,
    drawn: Vec<bool>,
    up: Vec<(u32, u32)>,
    /// Per border loop: the distance walked along it by the cut's border chain.
    walked: Vec<u64>,
    loops_touched: Vec<u32>,
    /// Per loop point: (outgoing, incoming) border-chain edges of the cut.
    degree: Vec<(u32, u32)>,
    points_touched: Vec<u32>,
}

impl Scratch {
    fn new(m: &BuiltMesh, p: &Prep) -> Self {
        Scratch {
            count: vec![[0; 2]; p.edges.len()],
            touched: Vec::new(),
            drawn: vec![false; m.clusters.len()],
            up: vec![(0, 0); m.clusters.len()],
            walked: vec![0; p.loop_len.len()],
            loops_touched: Vec::new(),
            degree: vec![(0, 0); p.loop_point.iter().filter(|&&x| x != u32::MAX).count()],
            points_touched: Vec::new(),
        }
    }
}

/// What one view found: its violation lines (in the reference's order), cut size and accepted
/// border edges.
struct ViewResult {
    violations: Vec<String>,
    /// Tested under partial residency.
    partial: bool,
    cut_triangles: usize,
    border_edges_accepted: usize,
}

fn check_cuts(m: &BuiltMesh, opts: &VerifyOptions, s: &mut Sink) {
    let positions = m.positions();
    let prep = Prep::new(m, &positions);
    s.r.border_loops = prep.loop_len.len();
    let (center, radius) = view_bounds(&positions);
    drop(positions);
    let scale = proj_scale(1080.0, 60f32.to_radians());
    let views = draw_views(center, radius, opts);
    let needs = super::page::group_needs(m);
    // Views in parallel; each thread takes a scratch from the pool (as many as run at once).
    let pool: Mutex<Vec<Scratch>> = Mutex::new(Vec::new());
    let results: Vec<ViewResult> = views
        .par_iter()
        .enumerate()
        .with_max_len(1)
        .map(|(view, &(cam, tau))| {
            let taken = pool.lock().map(|mut p| p.pop()).unwrap_or(None);
            let mut sc = taken.unwrap_or_else(|| Scratch::new(m, &prep));
            let res = view_residency(m, &needs, opts.seed, view);
            let r = check_view(m, &prep, view, (cam, tau), scale, res.as_deref(), &mut sc);
            if let Ok(mut p) = pool.lock() {
                p.push(sc);
            }
            r
        })
        .collect();
    s.r.cut_triangles_min = usize::MAX;
    for r in results {
        for v in r.violations {
            s.add(v);
        }
        s.r.cut_triangles_min = s.r.cut_triangles_min.min(r.cut_triangles);
        s.r.cut_triangles_max = s.r.cut_triangles_max.max(r.cut_triangles);
        s.r.border_edges_accepted += r.border_edges_accepted;
        s.r.views_tested += 1;
        s.r.residency_views += r.partial as usize;
    }
    if s.r.views_tested == 0 {
        s.r.cut_triangles_min = 0;
    }
}

/// How a view is named in violations.
pub(super) fn view_name(view: usize, cam: Vec3, tau: f32, res: Option<&[bool]>) -> String {
    match res {
        None => format!("view {view} (camera {:?}, tau {tau})", cam.to_array()),
        Some(r) => format!(
            "view {view} (camera {:?}, tau {tau}, {} of {} pages resident)",
            cam.to_array(),
            r.iter().filter(|&&x| x).count(),
            r.len()
        ),
    }
}

/// The checks of one view: the BVH cut equals the brute cut; every leaf-to-root path crosses the
/// cut once; the cut's edges match (no crack, no overlap) except simplified open borders, whose
/// chains must go once around their input border loop; at tau = 0 the cut is the input.
fn check_view(
    m: &BuiltMesh,
    p: &Prep,
    view: usize,
    (cam, tau): (Vec3, f32),
    scale: f32,
    res: Option<&[bool]>,
    sc: &mut Scratch,
) -> ViewResult {
    let mut out = Vec::new();
    let cut = cut_brute(m, cam, scale, tau, res);
    let what = view_name(view, cam, tau, res);
    match cut_bvh(m, cam, scale, tau, res) {
        Some(b) if b == cut => {}
        Some(b) => out.push(format!(
            "{what}: BVH cut has {} clusters, brute cut {}",
            b.len(),
            cut.len()
        )),
        None => out.push(format!("{what}: BVH traversal went out of range")),
    }
    // Every leaf-to-root path crosses the cut exactly once: (fewest, most) drawn clusters on the
    // paths from each cluster up, coarsest levels first.
    for &c in &cut {
        sc.drawn[c as usize] = true;
    }
    sc.up.fill((0, 0));
    for &c in &p.by_level {
        let cl = &m.clusters[c as usize];
        let d = sc.drawn[c as usize] as u32;
        sc.up[c as usize] = if c == m.root {
            (d, d)
        } else {
            let ps = &p.children[cl.group as usize];
            let mn = ps.iter().map(|&q| sc.up[q as usize].0).min().unwrap_or(0);
            let mx = ps.iter().map(|&q| sc.up[q as usize].1).max().unwrap_or(0);
            (d + mn, d + mx)
        };
    }
    for &c in &cut {
        sc.drawn[c as usize] = false;
    }
    let bad = p
        .level0
        .iter()
        .filter(|&&c| sc.up[c as usize] != (1, 1))
        .count();
    if bad > 0 {
        out.push(format!(
            "{what}: {bad} level-0 clusters not covered exactly once by the cut"
        ));
    }
    // Edge use counts of the cut (counted edges only).
    let mut cut_triangles = 0;
    for &c in &cut {
        let c = c as usize;
        cut_triangles += p.tri_off[c + 1] - p.tri_off[c];
        for u in &p.uses[p.use_off[c]..p.use_off[c + 1]] {
            let k = &mut sc.count[u.edge as usize];
            if *k == [0, 0] {
                sc.touched.push(u.edge);
            }
            k[0] += u.f as u32;
            k[1] += u.r as u32;
        }
    }
    let (mut cracks, mut overlaps, mut accepted) = (0usize, 0usize, 0usize);
    // The example: the reference reports the problem edge whose directed key comes first.
    let mut example: Option<(u64, [u32; 6])> = None;
    for &d in &sc.touched {
        let [fwd, back] = std::mem::take(&mut sc.count[d as usize]);
        let e = p.edges[d as usize];
        // Border chains: edges used once in one direction only, both ends on one simple loop.
        if e.x != e.y {
            for (a, b, f, r) in [(e.x, e.y, fwd, back), (e.y, e.x, back, fwd)] {
                let l = p.loop_of[a as usize];
                if f != 1 || r != 0 || l == u32::MAX || p.loop_of[b as usize] != l {
                    continue;
                }
                let len = p.loop_len[l as usize];
                let dist = (p.loop_idx[b as usize] + len - p.loop_idx[a as usize]) % len;
                if sc.walked[l as usize] == 0 {
                    sc.loops_touched.push(l);
                }
                sc.walked[l as usize] += dist as u64;
                for (q, out_edge) in [(a, true), (b, false)] {
                    let lp = p.loop_point[q as usize] as usize;
                    if sc.degree[lp] == (0, 0) {
                        sc.points_touched.push(lp as u32);
                    }
                    if out_edge {
                        sc.degree[lp].0 += 1;
                    } else {
                        sc.degree[lp].1 += 1;
                    }
                }
            }
        }
        // The reference visits an edge from x -> y if the cut uses that direction, else y -> x.
        let (a, b, f, r, f0, r0) = if fwd > 0 {
            (e.x, e.y, fwd, back, e.f0, e.r0)
        } else {
            (e.y, e.x, back, fwd, e.r0, e.f0)
        };
        if f == r || (f, r) == (f0, r0) {
            continue;
        }
        let (ai, bi) = (a as usize, b as usize);
        if f + r == 1 && p.border[ai] && p.border[bi] && p.comp[ai] == p.comp[bi] {
            accepted += 1;
            continue;
        }
        if f > 1 || r > 1 {
            overlaps += 1
        } else {
            cracks += 1
        }
        let key = (a as u64) << 32 | b as u64;
        if example.is_none_or(|(k, _)| key < k) {
            example = Some((key, [a, b, f, r, f0, r0]));
        }
    }
    sc.touched.clear();
    // A walk of 0 is impossible on a simple loop (distinct points), so walked != 0 marks the
    // touched loops; reset as we count.
    let mut bad_loops = 0;
    for &l in &sc.loops_touched {
        let w = std::mem::take(&mut sc.walked[l as usize]);
        if w != 0 && w != p.loop_len[l as usize] as u64 {
            bad_loops += 1;
        }
    }
    sc.loops_touched.clear();
    let mut bad_points = 0;
    for &q in &sc.points_touched {
        if std::mem::take(&mut sc.degree[q as usize]) != (1, 1) {
            bad_points += 1;
        }
    }
    sc.points_touched.clear();
    if bad_loops > 0 || bad_points > 0 {
        out.push(format!(
            "{what}: border chains broken on {bad_loops} of {} input border loops ({bad_points} points without one incoming and one outgoing border edge)",
            p.loop_len.len()
        ));
    }
    if let Some((_, [a, b, f, r, f0, r0])) = example {
        out.push(format!(
            "{what}: {cracks} unmatched and {overlaps} over-used edges, e.g. {:?} -> {:?} used {f}/{r} times (input: {f0}/{r0})",
            p.id_pos[a as usize], p.id_pos[b as usize]
        ));
    }
    if tau == 0.0 && res.is_none() {
        // The cut of exactly the level-0 clusters has the input's triangles by definition.
        let same = cut == p.level0 || {
            let orig = p.orig_tris.get_or_init(|| p.sorted_tris(&p.level0));
            p.sorted_tris(&cut) == *orig
        };
        if !same {
            out.push(format!(
                "{what}: tau = 0 cut has {cut_triangles} triangles, not the {} input triangles",
                p.level0_triangles
            ));
        }
    }
    ViewResult {
        violations: out,
        partial: res.is_some(),
        cut_triangles,
        border_edges_accepted: accepted,
    }
}
