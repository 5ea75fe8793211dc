//! BVH over groups (fanout 8, leaves of up to 4 groups): one subtree per build iteration (so that
//! a subtree's largest parent error is meaningful for LOD culling), joined under a top tree; laid
//! out breadth-first with no unreachable node.

use super::{BVH_FLAG_LEAF, BvhNode, Group, Sphere};

/// Most children per inner node.
pub const FANOUT: usize = 8;

fn merge(items: &[BvhNode]) -> BvhNode {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    let mut err = 0.0f32;
    let mut slo = [f32::MAX; 3];
    let mut shi = [f32::MIN; 3];
    for n in items {
        err = err.max(n.max_parent_error);
        for k in 0..3 {
            lo[k] = lo[k].min(n.bounds_min[k]);
            hi[k] = hi[k].max(n.bounds_max[k]);
            slo[k] = slo[k].min(n.lod_sphere[k] - n.lod_sphere[3]);
            shi[k] = shi[k].max(n.lod_sphere[k] + n.lod_sphere[3]);
        }
    }
    let c: [f32; 3] = std::array::from_fn(|k| (slo[k] + shi[k]) * 0.5);
    let mut r = 0.0f32;
    for it in items {
        let s = it.lod_sphere;
        let d = ((c[0] - s[0]) as f64)
            .hypot((c[1] - s[1]) as f64)
            .hypot((c[2] - s[2]) as f64) as f32;
        r = r.max(d + s[3]);
    }
    let mag = c[0].abs().max(c[1].abs()).max(c[2].abs());
    let r = r * (1.0 + 1e-5) + (mag + r) * 4e-7 + f32::MIN_POSITIVE;
    let lod_sphere: Sphere = [c[0], c[1], c[2], r];
    BvhNode {
        bounds_min: lo,
        max_parent_error: err,
        bounds_max: hi,
        flags: 0,
        lod_sphere,
        first: 0,
        count: 0,
        max_parent_coverage: 0.0,
        _pad: 0,
    }
}

/// Most groups per leaf.
pub const LEAF_GROUPS: usize = 4;

/// A node under construction.
struct Tmp {
    node: BvhNode,
    center: [f32; 3],
    /// Inner: children; leaf: empty (and `groups` set).
    children: Vec<Tmp>,
    groups: Vec<u32>,
}

fn center_of(n: &BvhNode) -> [f32; 3] {
    std::array::from_fn(|k| (n.bounds_min[k] + n.bounds_max[k]) * 0.5)
}

fn inner(children: Vec<Tmp>) -> Tmp {
    let node = merge(&children.iter().map(|c| c.node).collect::<Vec<_>>());
    Tmp {
        center: center_of(&node),
        node,
        children,
        groups: Vec::new(),
    }
}

/// Splits `items` into at most 8 spatially coherent runs (three rounds of median splits along the
/// longest axis of the centres); each run is non-empty.
fn split8<T>(mut items: Vec<T>, center: &dyn Fn(&T) -> [f32; 3]) -> Vec<Vec<T>> {
    let mut parts = vec![std::mem::take(&mut items)];
    for _ in 0..3 {
        let mut next = Vec::new();
        for mut p in parts {
            if p.len() <= 1 {
                next.push(p);
                continue;
            }
            let mut lo = [f32::MAX; 3];
            let mut hi = [f32::MIN; 3];
            for it in &p {
                let c = center(it);
                for k in 0..3 {
                    lo[k] = lo[k].min(c[k]);
                    hi[k] = hi[k].max(c[k]);
                }
            }
            let axis = (0..3)
                .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
                .unwrap_or(0);
            p.sort_by(|a, b| center(a)[axis].total_cmp(&center(b)[axis]));
            let b = p.split_off(p.len() / 2);
            next.push(p);
            next.push(b);
        }
        parts = next;
    }
    parts.into_iter().filter(|p| !p.is_empty()).collect()
}

/// Subtree over groups `ids` (leaves of at most [`LEAF_GROUPS`]).
fn build_groups(groups: &[Group], ids: Vec<u32>) -> Tmp {
    if ids.len() <= LEAF_GROUPS {
        let nodes: Vec<BvhNode> = ids
            .iter()
            .map(|&g| leaf_node(&groups[g as usize]))
            .collect();
        let mut node = merge(&nodes);
        node.flags = BVH_FLAG_LEAF;
        return Tmp {
            center: center_of(&node),
            node,
            children: Vec::new(),
            groups: ids,
        };
    }
    let center = |&g: &u32| center_of(&leaf_node(&groups[g as usize]));
    // Split into up to 8 children; with few groups, the children are leaves of up to
    // LEAF_GROUPS each.
    let parts = if ids.len() <= LEAF_GROUPS * FANOUT {
        let k = ids.len().div_ceil(LEAF_GROUPS).min(FANOUT);
        split_k(ids, k, &center)
    } else {
        split8(ids, &center)
    };
    inner(parts.into_iter().map(|p| build_groups(groups, p)).collect())
}

/// Splits into `k` runs of nearly equal size in the order of the longest axis of the centres.
fn split_k<T>(mut items: Vec<T>, k: usize, center: &dyn Fn(&T) -> [f32; 3]) -> Vec<Vec<T>> {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for it in &items {
        let c = center(it);
        for a in 0..3 {
            lo[a] = lo[a].min(c[a]);
            hi[a] = hi[a].max(c[a]);
        }
    }
    let axis = (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0);
    items.sort_by(|a, b| center(a)[axis].total_cmp(&center(b)[axis]));
    let n = items.len();
    let k = k.clamp(1, n.max(1));
    let mut out = Vec::with_capacity(k);
    let mut it = items.into_iter();
    for i in 0..k {
        let size = n * (i + 1) / k - n * i / k;
        out.push(it.by_ref().take(size).collect::<Vec<T>>());
    }
    out.into_iter().filter(|p| !p.is_empty()).collect()
}

/// Tree over subtrees (fanout 8).
fn build_top(mut items: Vec<Tmp>) -> Tmp {
    if items.len() == 1
        && let Some(t) = items.pop()
    {
        return t;
    }
    if items.len() <= FANOUT {
        return inner(items);
    }
    let parts = split8(items, &|t: &Tmp| t.center);
    inner(parts.into_iter().map(build_top).collect())
}

fn leaf_node(g: &Group) -> BvhNode {
    BvhNode {
        bounds_min: g.bounds_min,
        max_parent_error: g.error,
        bounds_max: g.bounds_max,
        flags: BVH_FLAG_LEAF,
        lod_sphere: g.lod_sphere,
        first: 0,
        count: 0,
        max_parent_coverage: 0.0,
        _pad: 0,
    }
}

/// Builds the BVH over `groups`: one subtree per build iteration (so that a subtree's largest
/// parent error is meaningful for LOD culling) joined under a top tree of fanout 8. Returns the
/// nodes (node 0 is the root; every node is reachable; an inner node's children are contiguous)
/// and the order in which the groups must be stored so that each leaf's groups `first .. first +
/// count` are contiguous: `order[i]` is the input index of stored group `i`.
pub fn build_bvh(groups: &[Group]) -> (Vec<BvhNode>, Vec<u32>) {
    if groups.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let mut by_iter: Vec<u32> = (0..groups.len() as u32).collect();
    by_iter.sort_by_key(|&g| (groups[g as usize].iteration, g));
    let mut subtrees = Vec::new();
    let mut i = 0;
    while i < by_iter.len() {
        let it = groups[by_iter[i] as usize].iteration;
        let mut j = i;
        while j < by_iter.len() && groups[by_iter[j] as usize].iteration == it {
            j += 1;
        }
        subtrees.push(build_groups(groups, by_iter[i..j].to_vec()));
        i = j;
    }
    let root = build_top(subtrees);
    // Breadth-first layout: children of a node are allocated together.
    let mut nodes = vec![root.node];
    let mut order = Vec::with_capacity(groups.len());
    let mut queue = std::collections::VecDeque::new();
    queue.push_back((0usize, root));
    while let Some((slot, t)) = queue.pop_front() {
        if t.children.is_empty() {
            nodes[slot].flags = BVH_FLAG_LEAF;
            nodes[slot].first = order.len() as u32;
            nodes[slot].count = t.groups.len() as u32;
            order.extend_from_slice(&t.groups);
        } else {
            let first = nodes.len();
            nodes[slot].flags = 0;
            nodes[slot].first = first as u32;
            nodes[slot].count = t.children.len() as u32;
            for (k, c) in t.children.into_iter().enumerate() {
                nodes.push(c.node);
                queue.push_back((first + k, c));
            }
        }
    }
    (nodes, order)
}

/// Sets every node's `max_parent_coverage`: the largest of `group_coverage` (per stored group) over
/// its subtree. Children come after their parent (breadth-first), so one backward pass does.
pub fn set_max_parent_coverage(bvh: &mut [BvhNode], group_coverage: &[f32]) {
    for i in (0..bvh.len()).rev() {
        let n = bvh[i];
        let (first, count) = (n.first as usize, n.count as usize);
        bvh[i].max_parent_coverage = if n.flags & BVH_FLAG_LEAF != 0 {
            group_coverage
                .get(first..first + count)
                .unwrap_or(&[])
                .iter()
                .fold(0.0, |a, &b| a.max(b))
        } else {
            bvh.get(first..first + count)
                .unwrap_or(&[])
                .iter()
                .fold(0.0, |a, c| a.max(c.max_parent_coverage))
        };
    }
}
