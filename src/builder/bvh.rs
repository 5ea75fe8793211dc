//! BVH over groups (fanout 8): one subtree per build iteration (so that a subtree's largest parent
//! error is meaningful for LOD culling), joined under a top tree.

use super::{BVH_FLAG_LEAF, BvhNode, Group, Sphere};

const FANOUT: usize = 8;

#[derive(Clone, Copy)]
struct Item {
    node: BvhNode,
    center: [f32; 3],
}

fn merge(items: &[Item]) -> BvhNode {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    let mut err = 0.0f32;
    let mut slo = [f32::MAX; 3];
    let mut shi = [f32::MIN; 3];
    for it in items {
        let n = &it.node;
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
        let s = it.node.lod_sphere;
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
        _pad: [0; 2],
    }
}

/// Splits `items` into at most 8 spatially coherent chunks (three rounds of median splits along the
/// longest axis of the centres).
fn split8(items: &mut [Item]) -> Vec<std::ops::Range<usize>> {
    let mut ranges: Vec<std::ops::Range<usize>> = std::iter::once(0..items.len()).collect();
    for _ in 0..3 {
        let mut next = Vec::new();
        for r in ranges {
            if r.len() <= 1 {
                next.push(r);
                continue;
            }
            let slice = &mut items[r.clone()];
            let mut lo = [f32::MAX; 3];
            let mut hi = [f32::MIN; 3];
            for it in slice.iter() {
                for k in 0..3 {
                    lo[k] = lo[k].min(it.center[k]);
                    hi[k] = hi[k].max(it.center[k]);
                }
            }
            let axis = (0..3)
                .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
                .unwrap_or(0);
            slice.sort_by(|a, b| a.center[axis].total_cmp(&b.center[axis]));
            let mid = r.start + r.len() / 2;
            next.push(r.start..mid);
            next.push(mid..r.end);
        }
        ranges = next;
    }
    ranges.into_iter().filter(|r| !r.is_empty()).collect()
}

/// Fills `nodes[slot]` with a subtree over `items`.
fn build_into(nodes: &mut Vec<BvhNode>, slot: usize, items: &mut [Item]) {
    if items.len() == 1 {
        nodes[slot] = items[0].node;
        return;
    }
    let mut node = merge(items);
    let chunks: Vec<std::ops::Range<usize>> = if items.len() <= FANOUT {
        (0..items.len()).map(|i| i..i + 1).collect()
    } else {
        split8(items)
    };
    let first = nodes.len();
    nodes.resize(first + chunks.len(), BvhNode::default_zeroed());
    node.first = first as u32;
    node.count = chunks.len() as u32;
    nodes[slot] = node;
    for (i, r) in chunks.into_iter().enumerate() {
        build_into(nodes, first + i, &mut items[r]);
    }
}

impl BvhNode {
    fn default_zeroed() -> Self {
        bytemuck::Zeroable::zeroed()
    }
}

/// Builds the BVH over `groups`; node 0 is the root. Leaves reference one group each.
pub fn build_bvh(groups: &[Group]) -> Vec<BvhNode> {
    if groups.is_empty() {
        return Vec::new();
    }
    let leaf = |gi: usize| {
        let g = &groups[gi];
        Item {
            node: BvhNode {
                bounds_min: g.bounds_min,
                max_parent_error: g.error,
                bounds_max: g.bounds_max,
                flags: BVH_FLAG_LEAF,
                lod_sphere: g.lod_sphere,
                first: gi as u32,
                count: 1,
                _pad: [0; 2],
            },
            center: std::array::from_fn(|k| (g.bounds_min[k] + g.bounds_max[k]) * 0.5),
        }
    };
    // Buckets by iteration (groups are stored in iteration order).
    let mut buckets: Vec<Vec<Item>> = Vec::new();
    let mut last = None;
    for (gi, g) in groups.iter().enumerate() {
        if last != Some(g.iteration) {
            buckets.push(Vec::new());
            last = Some(g.iteration);
        }
        if let Some(b) = buckets.last_mut() {
            b.push(leaf(gi));
        }
    }
    let mut nodes = vec![BvhNode::default_zeroed()];
    if buckets.len() == 1 {
        build_into(&mut nodes, 0, &mut buckets[0]);
        return nodes;
    }
    // Subtrees per bucket, built in place: their roots become the items of the top tree.
    let mut roots = Vec::new();
    for b in &mut buckets {
        let slot = nodes.len();
        nodes.push(BvhNode::default_zeroed());
        build_into(&mut nodes, slot, b);
        let n = nodes[slot];
        let center = std::array::from_fn(|k| (n.bounds_min[k] + n.bounds_max[k]) * 0.5);
        roots.push(Item { node: n, center });
    }
    // The top tree: items copy the subtree roots (whose children indices stay valid).
    build_into(&mut nodes, 0, &mut roots);
    nodes
}
