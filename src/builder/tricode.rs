//! A cluster's triangles as stored in an encoded page: the *max-delta* code.
//!
//! The builder gives every cluster a canonical triangle order ([`canonical_order`]): its vertices
//! are numbered in order of first use, each triangle is rotated (winding kept) so that its first
//! corner is its largest local index `m`, and the triangles are sorted by `m` (stably). Then `m`
//! never decreases from one triangle to the next and grows by at most 3 (a triangle that brings
//! `k` new vertices has the newest as its largest), so a triangle is stored as
//!
//! - `Δ = m - m_prev` in 2 bits (`m_prev` = -1 before the first triangle), and
//! - its two other corners as `m - 1 - corner`, each in `w` bits (`w` per cluster: the fewest that
//!   hold every such offset, at least 1),
//!
//! about 11 bits a triangle on the scans (`w` = 4 in the band order of [`stored_order`]; 12-15
//! with `w` = 5-6 before it) instead of 3 x 7 for plain packed indices. Any triangle is decoded
//! without the ones before it: the `Δ`s sit in one word per block of 12 triangles with the
//! block's base, and a triangle's `m` is that base plus a population count of the `Δ` bits up to
//! it.
//!
//! Layout: a header `w`, which the page stores in the low [`crate::shared::TRIANGLE_HEAD_BITS`] of
//! the spare high bits of the cluster's smallest x grid coordinate (above
//! [`crate::shared::CLUSTER_COORD_BITS`]), so that a reader has it with the rest of the cluster's
//! code; then u32 words, little-endian:
//! - one word per block of 12 triangles: their 2-bit `Δ`s (triangle `t` at bit `2 (t % 12)`) and,
//!   in bits 24-31, the block's base, `m + 1` at the end of the block before (0 for the first);
//! - the corner offsets: triangle `t`'s two `w`-bit fields at bit `2 w t` of one bit stream.
//!
//! A cluster whose triangles are not in canonical order (only hand-made test meshes), or whose
//! code would not be shorter (a few triangles), has header 0 and its plain packed indices
//! ([`super::pack_indices`]). The GPU's decoder is `cluster_triangle` in
//! `shaders_glsl/common/raster.glsl`; [`decode`] is the CPU's.

use super::page::{BitWriter, get_bits};

/// Triangles per word of `Δ`s (24 bits, the block's base in the other 8).
const BLOCK: usize = crate::shared::TRIANGLE_CODE_BLOCK as usize;
const _: () = assert!(2 * BLOCK + 8 <= 32);

/// Bits needed for values `0 ..= x`.
fn width(x: u32) -> u32 {
    32 - x.leading_zeros()
}

/// Puts a cluster's triangles (local indices, vertices numbered in order of first use by these
/// triangles in this order) in canonical order: each rotated to start at its largest index,
/// then sorted stably by that index. A triangle for which `rotatable` is false keeps its first
/// corner (a triangle's material is its first vertex's: one whose corners have several materials
/// would change); if its largest index is not first, the cluster is not canonical and keeps plain
/// packed indices ([`encode`]).
pub fn canonical_order(tris: &mut [[u32; 3]], rotatable: &dyn Fn(&[u32; 3]) -> bool) {
    for t in tris.iter_mut() {
        if rotatable(t) {
            let r = (0..3)
                .max_by_key(|&k| (t[k], std::cmp::Reverse(k)))
                .unwrap_or(0);
            *t = [t[r], t[(r + 1) % 3], t[(r + 2) % 3]];
        }
    }
    // Stable by the largest index: sorted as (largest, position) pairs packed in one word.
    let mut keyed: Vec<u64> = tris
        .iter()
        .enumerate()
        .map(|(i, t)| u64::from(t[0].max(t[1]).max(t[2])) << 32 | i as u64)
        .collect();
    keyed.sort_unstable();
    let sorted: Vec<[u32; 3]> = keyed.iter().map(|&k| tris[k as u32 as usize]).collect();
    tris.copy_from_slice(&sorted);
}

/// A cluster's triangles (mesh vertex ids) in the order that stores them in the fewest words:
/// its local vertices (mesh ids, numbered in order of first use) and its local triangles in
/// canonical order ([`canonical_order`]; `rotatable` is asked with mesh ids).
///
/// The max-delta code stores two corner offsets per triangle in the cluster's widest offset's
/// bits, so the fewest bits come from a vertex numbering in which every triangle's corners lie
/// close together: a band. Besides the order given, it tries the orders of breadth-first
/// numberings of the vertex graph (reverse Cuthill-McKee without the reversal: neighbours by
/// increasing degree, from the end of two sweeps from each of three starts: the vertex of least
/// degree, the first, the middle), the triangles sorted by their largest and smallest number,
/// and keeps the one whose code takes the fewest words (the first on ties: deterministic). On
/// the scans the offsets' width drops from 5-6 to 4 bits: 12.9 -> 11.0 bits a triangle (turbine
/// blade).
pub fn stored_order(
    tris: &[[u32; 3]],
    vertex_count: usize,
    rotatable: &dyn Fn(&[u32; 3]) -> bool,
) -> (Vec<u32>, Vec<[u32; 3]>) {
    // An order's local vertices (first use) and its triangles in those numbers.
    let numbered = |order: &[[u32; 3]]| -> (Vec<u32>, Vec<[u32; 3]>) {
        let (local, idx) = super::simplify::compact(order, vertex_count);
        (
            local,
            idx.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
        )
    };
    // ... put in canonical order, with its code's words.
    let coded = |(local, mut lt): (Vec<u32>, Vec<[u32; 3]>)| {
        canonical_order(&mut lt, &|t| rotatable(&t.map(|l| local[l as usize])));
        let words = encoded_words(&lt, local.len() as u32);
        (local, lt, words)
    };
    // The given order; the band orders number its local vertices (`local_tris`: its triangles
    // in the given order, in those numbers).
    let given = numbered(tris);
    let local_tris = given.1.clone();
    let mut best = coded(given);
    let n = best.0.len();
    if n < 2 {
        return (best.0, best.1);
    }
    let mut adj: Vec<Vec<u32>> = vec![Vec::new(); n];
    for t in &local_tris {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a != b && !adj[a as usize].contains(&b) {
                adj[a as usize].push(b);
                adj[b as usize].push(a);
            }
        }
    }
    // Neighbours by increasing degree (then id), once: what each numbering visits in order.
    let degree: Vec<usize> = adj.iter().map(Vec::len).collect();
    for a in &mut adj {
        a.sort_unstable_by_key(|&v| (degree[v as usize], v));
    }
    // Breadth-first numbering from `s` into `out`; a vertex not reached (another piece) starts
    // over from the first one left.
    let mut seen = vec![false; n];
    let mut bfs = |s: u32, out: &mut Vec<u32>| {
        seen.fill(false);
        out.clear();
        let mut next_unseen = 0usize;
        let mut start = s;
        loop {
            seen[start as usize] = true;
            out.push(start);
            let mut i = out.len() - 1;
            while i < out.len() {
                let u = out[i];
                i += 1;
                for &v in &adj[u as usize] {
                    if !seen[v as usize] {
                        seen[v as usize] = true;
                        out.push(v);
                    }
                }
            }
            while next_unseen < n && seen[next_unseen] {
                next_unseen += 1;
            }
            if next_unseen == n {
                return;
            }
            start = next_unseen as u32;
        }
    };
    let least = (0..n as u32)
        .min_by_key(|&v| (degree[v as usize], v))
        .unwrap_or(0);
    let mut numbering = Vec::with_capacity(n);
    let mut tried = Vec::new();
    for s0 in [least, 0, n as u32 / 2] {
        let mut s = s0;
        for _ in 0..2 {
            bfs(s, &mut numbering);
            s = *numbering.last().unwrap_or(&s);
        }
        if tried.contains(&s) {
            continue;
        }
        tried.push(s);
        bfs(s, &mut numbering);
        let mut pos = vec![0u32; n];
        for (i, &v) in numbering.iter().enumerate() {
            pos[v as usize] = i as u32;
        }
        let mut order: Vec<(u32, u32, usize)> = local_tris
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let p = t.map(|v| pos[v as usize]);
                (p[0].max(p[1]).max(p[2]), p[0].min(p[1]).min(p[2]), i)
            })
            .collect();
        order.sort_unstable();
        let permuted: Vec<[u32; 3]> = order.iter().map(|&(_, _, i)| tris[i]).collect();
        let c = coded(numbered(&permuted));
        if c.2 < best.2 {
            best = c;
        }
    }
    (best.0, best.1)
}

/// The corner offsets' width of `tris`' max-delta code (`None` when they are not in canonical
/// order).
fn max_delta_width(tris: &[[u32; 3]]) -> Option<u32> {
    if tris.is_empty() {
        return None;
    }
    let mut prev = -1i64;
    let mut widest = 0u32;
    for t in tris {
        let d = t[0] as i64 - prev;
        if !(0..=3).contains(&d) || t[1] >= t[0] || t[2] >= t[0] || t[0] > 255 {
            return None;
        }
        prev = t[0] as i64;
        widest = widest.max(t[0] - 1 - t[1]).max(t[0] - 1 - t[2]);
    }
    Some(width(widest).max(1))
}

/// Words of the max-delta code of `n` triangles with offsets of `w` bits (header not counted).
fn max_delta_words(n: usize, w: u32) -> usize {
    n.div_ceil(BLOCK) + (2 * w as usize * n).div_ceil(32)
}

/// The max-delta code of `tris` (canonical, offsets of `w` bits; its header is `w`).
fn encode_max_delta(tris: &[[u32; 3]], w: u32) -> Vec<u32> {
    let mut out = Vec::with_capacity(max_delta_words(tris.len(), w) + 1);
    let mut prev = -1i64;
    for (i, t) in tris.iter().enumerate() {
        if i % BLOCK == 0 {
            out.push(((prev + 1) as u32) << 24);
        }
        let d = (t[0] as i64 - prev) as u32;
        *out.last_mut().expect("a block word") |= d << (2 * (i % BLOCK));
        prev = t[0] as i64;
    }
    let start = out.len();
    let mut bits = BitWriter {
        out: &mut out,
        start,
        bit: 0,
    };
    for t in tris {
        bits.put(t[0] - 1 - t[1], w);
        bits.put(t[0] - 1 - t[2], w);
    }
    out.resize(max_delta_words(tris.len(), w), 0);
    out
}

/// Whether `tris` take the max-delta code, and its offsets' width: canonical and shorter than
/// the plain packed indices.
fn max_delta_choice(tris: &[[u32; 3]], vertex_count: u32) -> Option<u32> {
    let plain_words = super::packed_triangle_bytes(vertex_count, tris.len() as u32) / 4;
    max_delta_width(tris).filter(|&w| max_delta_words(tris.len(), w) < plain_words)
}

/// Words of [`encode`]'s code for `tris` (header not counted), without encoding them.
pub fn encoded_words(tris: &[[u32; 3]], vertex_count: u32) -> usize {
    match max_delta_choice(tris, vertex_count) {
        Some(w) => max_delta_words(tris.len(), w),
        None => super::packed_triangle_bytes(vertex_count, tris.len() as u32) / 4,
    }
}

/// A cluster's triangles in stored form, its header and its words: the max-delta code, or
/// header 0 and the plain packed indices (`vertex_count` sets their width) when `tris` are not in
/// canonical order or the code would not be shorter (a few triangles).
pub fn encode(tris: &[[u32; 3]], vertex_count: u32) -> (u32, Vec<u32>) {
    if let Some(w) = max_delta_choice(tris, vertex_count) {
        return (w, encode_max_delta(tris, w));
    }
    let local: Vec<u8> = tris.iter().flatten().map(|&v| v as u8).collect();
    let mut bytes = Vec::new();
    super::pack_indices(&local, vertex_count, &mut bytes);
    let words = bytes
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    (0, words)
}

/// Decodes `triangle_count` triangles of a cluster of `vertex_count` vertices, whose header
/// is `head`, from the start of `words`, and returns them with the words they took. An error says
/// what does not fit: data past the end, an index not below the vertex count, a code that is not
/// the one [`encode`] gives for its triangles.
pub fn decode(
    head: u32,
    words: &[u32],
    triangle_count: u32,
    vertex_count: u32,
) -> Result<(Vec<[u32; 3]>, usize), String> {
    let tc = triangle_count as usize;
    let w = head & 0xff;
    let tris: Vec<[u32; 3]> = if w == 0 {
        let n = super::packed_triangle_bytes(vertex_count, triangle_count) / 4;
        let body = words
            .get(..n)
            .ok_or("packed triangles past the page's end")?;
        let bytes: &[u8] = bytemuck::cast_slice(body);
        let bits = super::index_bits(vertex_count);
        (0..tc)
            .map(|t| {
                std::array::from_fn(|k| {
                    super::unpack_index(bytes, bits, 3 * t + k).unwrap_or(u32::MAX)
                })
            })
            .collect()
    } else {
        if w > 8 || tc == 0 {
            return Err(format!(
                "triangle code width {w} for {tc} triangles (1..=8 and at least 1 expected)"
            ));
        }
        let stream = tc.div_ceil(BLOCK);
        let n = stream + (2 * w as usize * tc).div_ceil(32);
        let body = words.get(..n).ok_or("triangle code past the page's end")?;
        (0..tc)
            .map(|t| {
                let m = max_index(body, t);
                let f = |k: usize| {
                    get_bits(&body[stream..], (2 * t + k) * w as usize, w).unwrap_or(u32::MAX)
                };
                [m, m.wrapping_sub(1 + f(0)), m.wrapping_sub(1 + f(1))]
            })
            .collect()
    };
    if let Some(l) = tris.iter().flatten().find(|&&l| l >= vertex_count) {
        return Err(format!("local index {l} >= vertex count {vertex_count}"));
    }
    let (again_head, again) = encode(&tris, vertex_count);
    if again_head != head || words.get(..again.len()) != Some(&again[..]) {
        return Err("the triangle code is not the one its triangles give".into());
    }
    Ok((tris, again.len()))
}

/// Triangle `t`'s largest index: its block's base plus the block's `Δ`s up to it (as the GPU
/// computes it).
fn max_index(code: &[u32], t: usize) -> u32 {
    let x = code[t / BLOCK];
    let steps = x & ((1 << (2 * (t % BLOCK) + 2)) - 1);
    // A 2-bit field's value is its set bits plus its set high bit.
    ((x >> 24) + steps.count_ones() + (steps & 0x00aa_aaaa).count_ones()).wrapping_sub(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of `n` triangles over vertices numbered in order of first use.
    fn strip(n: u32) -> Vec<[u32; 3]> {
        (0..n)
            .map(|i| {
                if i % 2 == 0 {
                    [i, i + 1, i + 2]
                } else {
                    [i + 1, i, i + 2]
                }
            })
            .collect()
    }

    /// A triangle as its smallest rotation: equal for two triangles with the same corners in the
    /// same cyclic order (winding).
    fn cyc(t: [u32; 3]) -> [u32; 3] {
        (0..3)
            .map(|r| [t[r], t[(r + 1) % 3], t[(r + 2) % 3]])
            .min()
            .unwrap_or(t)
    }

    /// A grid patch of `w` x `h` quads (two triangles each, counter-clockwise), vertex ids
    /// `base + x + y (w + 1)`, in a scrambled order (a fixed permutation).
    fn scrambled_patch(w: u32, h: u32, base: u32) -> Vec<[u32; 3]> {
        let id = |x: u32, y: u32| base + x + y * (w + 1);
        let mut t = Vec::new();
        for y in 0..h {
            for x in 0..w {
                t.push([id(x, y), id(x + 1, y), id(x + 1, y + 1)]);
                t.push([id(x, y), id(x + 1, y + 1), id(x, y + 1)]);
            }
        }
        let n = t.len();
        (0..n).map(|i| t[(i * 37 + 11) % n]).collect()
    }

    #[test]
    fn stored_order_keeps_the_triangles_and_bands_the_offsets() {
        // A 8 x 8 grid patch (128 triangles, 81 vertices), scrambled; and the same with a
        // second piece and vertex ids far apart. The result: the same triangles (mesh ids, each
        // with its winding), local vertices in order of first use, canonical, and its code
        // shorter than that of the given order, with offsets of at most 4 bits (a band of about
        // the grid's width); the given order's code needs 7.
        for tris in [scrambled_patch(8, 8, 1000), {
            let mut t = scrambled_patch(6, 5, 0);
            t.extend(scrambled_patch(3, 4, 90_000));
            t
        }] {
            let vertex_count = 100_000;
            let (local, lt) = stored_order(&tris, vertex_count, &|_| true);
            let mut a: Vec<_> = tris.iter().map(|&t| cyc(t)).collect();
            let mut b: Vec<_> = lt
                .iter()
                .map(|t| cyc(t.map(|l| local[l as usize])))
                .collect();
            a.sort();
            b.sort();
            assert_eq!(a, b, "the same triangles with their windings");
            let mut first_use = Vec::new();
            for &l in lt.iter().flatten() {
                if !first_use.contains(&l) {
                    first_use.push(l);
                }
            }
            let mut sorted_use = first_use.clone();
            sorted_use.sort();
            assert_eq!(sorted_use, (0..local.len() as u32).collect::<Vec<_>>());
            let given = {
                let (gl, idx) = super::super::simplify::compact(&tris, vertex_count);
                let mut g: Vec<[u32; 3]> =
                    idx.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
                canonical_order(&mut g, &|_| true);
                (max_delta_width(&g), encoded_words(&g, gl.len() as u32))
            };
            let w = max_delta_width(&lt).expect("canonical");
            assert!(w <= 4, "offsets of {w} bits (given order: {:?})", given.0);
            assert!(given.0.expect("canonical") >= 6, "{:?}", given.0);
            assert!(encoded_words(&lt, local.len() as u32) < given.1);
            let (head, code) = encode(&lt, local.len() as u32);
            assert_eq!(head, w);
            let back = decode(head, &code, lt.len() as u32, local.len() as u32).expect("decode");
            assert_eq!(back.0, lt);
        }
    }

    #[test]
    fn canonical_triangles_round_trip_in_fewer_words() {
        for n in [1, 2, 11, 12, 13, 31, 64, 100, 128] {
            let mut t = strip(n);
            let vc = n + 2;
            canonical_order(&mut t, &|_| true);
            let (head, code) = encode(&t, vc);
            assert_eq!(head == 0, n < 11, "{n}: {head:#x} {code:?}");
            let (back, used) = decode(head, &code, n, vc).expect("decode");
            assert_eq!(back, t, "{n}");
            assert_eq!(used, code.len());
            let plain = super::super::packed_triangle_bytes(vc, n) / 4;
            assert!(code.len() <= plain, "{n}: {} words vs {plain}", code.len());
            assert_eq!(encoded_words(&t, vc), code.len(), "{n}");
        }
    }

    #[test]
    fn canonical_order_keeps_winding_and_bounds_the_steps() {
        // A fan and a grid: every triangle keeps its cyclic order; m grows by at most 3.
        let mut t: Vec<[u32; 3]> = (1..20).map(|i| [0, i, i + 1]).collect();
        t.extend([[30, 25, 21], [22, 30, 21]]);
        let mut labels = std::collections::HashMap::new();
        let mut l: Vec<[u32; 3]> = t
            .iter()
            .map(|t| {
                t.map(|v| {
                    let n = labels.len() as u32;
                    *labels.entry(v).or_insert(n)
                })
            })
            .collect();
        let before = l.clone();
        canonical_order(&mut l, &|_| true);
        let mut a: Vec<_> = before.iter().map(|&t| cyc(t)).collect();
        let mut b: Vec<_> = l.iter().map(|&t| cyc(t)).collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
        let (head, code) = encode(&l, labels.len() as u32);
        assert_ne!(head, 0);
        assert_eq!(
            decode(head, &code, l.len() as u32, labels.len() as u32)
                .unwrap()
                .0,
            l
        );
    }

    #[test]
    fn canonical_order_is_a_stable_sort_by_the_largest_index() {
        // Pseudo-random triangles with many equal largest indices and some that may not rotate:
        // the order is that of a stable sort of the rotated triangles by their largest index.
        let mut rng = crate::builder::verify::Rng(7);
        let mut next = || (rng.next() % 24) as u32;
        let tris: Vec<[u32; 3]> = (0..128).map(|_| [next(), next(), next()]).collect();
        let rotatable = |t: &[u32; 3]| !(t[0] + t[1] + t[2]).is_multiple_of(5);
        let mut want: Vec<[u32; 3]> = tris
            .iter()
            .map(|t| {
                if rotatable(t) {
                    let r = (0..3)
                        .max_by_key(|&k| (t[k], std::cmp::Reverse(k)))
                        .unwrap();
                    [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]
                } else {
                    *t
                }
            })
            .collect();
        want.sort_by_key(|t| *t.iter().max().unwrap());
        let mut got = tris.clone();
        canonical_order(&mut got, &rotatable);
        assert_eq!(got, want);
    }

    #[test]
    fn a_triangle_that_may_not_rotate_keeps_its_first_corner() {
        let mut t = strip(20);
        // Triangle 5 ([6, 5, 7]) keeps 6 first: the cluster is stored plain, with that corner.
        canonical_order(&mut t, &|t| t.iter().copied().min() != Some(5));
        assert!(t.contains(&[6, 5, 7]));
        let (head, code) = encode(&t, 22);
        assert_eq!(head, 0);
        assert_eq!(decode(head, &code, 20, 22).unwrap().0, t);
    }

    #[test]
    fn other_orders_are_stored_plain_and_bad_codes_refused() {
        let t = vec![[0, 1, 2], [2, 1, 3], [0, 2, 1]];
        let (head, code) = encode(&t, 4);
        assert_eq!(head, 0);
        assert_eq!(decode(head, &code, 3, 4).unwrap().0, t);
        let mut c = strip(40);
        canonical_order(&mut c, &|_| true);
        let (head, good) = encode(&c, 42);
        assert!(decode(head, &good, 40, 42).is_ok());
        // An index past the vertex count.
        assert!(decode(head, &good, 40, 30).is_err());
        // A wider code than needed.
        assert!(decode((head & !0xff) | 8, &good, 40, 42).is_err());
        // Truncated.
        assert!(decode(head, &good[..3], 40, 42).is_err());
        // A corner offset that reaches below 0.
        let mut under = good.clone();
        let last = under.len() - 1;
        under[last] = u32::MAX;
        assert!(decode(head, &under, 40, 42).is_err());
    }
}
