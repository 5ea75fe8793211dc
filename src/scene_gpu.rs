//! The vgeo path's scene on the GPU: every mesh's cluster DAG in shared buffers (uploaded once) and
//! the instances. Nothing here changes per frame; the per-frame data is [`crate::shared::ViewGpu`].

use std::borrow::Borrow;

use glam::{DMat4, DVec3, Mat3};

use crate::builder::BuiltMesh;
use crate::gpu::{Buffer, Context, Desc, GpuError, GpuResult, vk};
use crate::render::Placement;
use crate::shared::{GpuVertex, InstanceVgeo, MeshGpu, NO_UVS};

/// Splits an f64 into a high f32 and the f32 of the remainder (`hi + lo` is exact to ~1e-14 relative).
pub fn split_f64(v: f64) -> (f32, f32) {
    let hi = v as f32;
    (hi, (v - hi as f64) as f32)
}

/// The GPU form of one placement.
pub fn instance_gpu(p: &Placement) -> InstanceVgeo {
    let m: DMat4 = p.transform;
    let lin = Mat3::from_cols(
        m.x_axis.truncate().as_vec3(),
        m.y_axis.truncate().as_vec3(),
        m.z_axis.truncate().as_vec3(),
    );
    let t: DVec3 = m.w_axis.truncate();
    let (hx, lx) = split_f64(t.x);
    let (hy, ly) = split_f64(t.y);
    let (hz, lz) = split_f64(t.z);
    let max_scale = crate::render::max_axis_scale(&m);
    InstanceVgeo {
        linear: [
            lin.x_axis.extend(0.0).into(),
            lin.y_axis.extend(0.0).into(),
            lin.z_axis.extend(0.0).into(),
        ],
        translation_hi: [hx, hy, hz],
        mesh: p.mesh,
        translation_lo: [lx, ly, lz],
        max_scale,
        color: p.color,
        visible_base: 0,
    }
}

/// Bounding sphere (center, radius) of a built mesh's level-0 bounds.
fn mesh_sphere(m: &BuiltMesh) -> ([f32; 3], f32) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for c in &m.clusters {
        for k in 0..3 {
            lo[k] = lo[k].min(c.bounds_min[k]);
            hi[k] = hi[k].max(c.bounds_max[k]);
        }
    }
    if !lo[0].is_finite() {
        return ([0.0; 3], 0.0);
    }
    let c = [
        (lo[0] + hi[0]) * 0.5,
        (lo[1] + hi[1]) * 0.5,
        (lo[2] + hi[2]) * 0.5,
    ];
    let r =
        ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt() * 0.5;
    (c, r * 1.0001)
}

/// All meshes' DAG data and the instances, in GPU buffers.
pub struct GpuScene {
    pub meshes: Buffer,
    pub instances: Buffer,
    pub clusters: Buffer,
    pub groups: Buffer,
    pub bvh: Buffer,
    pub vertices: Buffer,
    /// Texture coordinates (2 x 16 bits) of the meshes with UVs (`MeshGpu::uv_offset`).
    pub uvs: Buffer,
    pub vertex_refs: Buffer,
    /// Local triangle indices, 3 bytes per triangle, packed into u32 words (little-endian).
    pub triangles: Buffer,
    pub mesh_table: Vec<MeshGpu>,
    pub instance_count: u32,
    pub total_clusters: u32,
    /// Sum over instances of their mesh's cluster count: the visible-list length that direct slots
    /// need (see [`crate::shared::VIEW_FLAG_DIRECT_VISIBLE`]).
    pub instance_clusters: u64,
}

impl GpuScene {
    /// Uploads `built` meshes and `placements` (whose `mesh` indexes `built`).
    pub fn new<B: Borrow<BuiltMesh>>(
        ctx: &Context,
        built: &[B],
        placements: &[Placement],
    ) -> GpuResult<Self> {
        if let Some(p) = placements.iter().find(|p| p.mesh as usize >= built.len()) {
            return Err(GpuError::Other(format!(
                "placement refers to mesh {} of {}",
                p.mesh,
                built.len()
            )));
        }
        let mut table = Vec::with_capacity(built.len());
        let (mut clusters, mut groups, mut bvh, mut vertices, mut refs, mut tris) = (
            Vec::new(),
            Vec::new(),
            Vec::new(),
            Vec::<GpuVertex>::new(),
            Vec::new(),
            Vec::new(),
        );
        let mut uvs: Vec<u32> = Vec::new();
        for m in built {
            let m = m.borrow();
            let (center, radius) = mesh_sphere(m);
            let q = &m.quantization;
            table.push(MeshGpu {
                cluster_offset: clusters.len() as u32,
                group_offset: groups.len() as u32,
                bvh_offset: bvh.len() as u32,
                vertex_offset: vertices.len() as u32,
                vertex_ref_offset: refs.len() as u32,
                triangle_offset: tris.len() as u32,
                cluster_count: m.clusters.len() as u32,
                bvh_root: 0,
                quant_origin: [q.origin[0] as f32, q.origin[1] as f32, q.origin[2] as f32],
                quant_step: q.step as f32,
                bounds_center: center,
                bounds_radius: radius,
                root_cluster: m.root,
                fallback_level: m
                    .fallback_level(crate::builder::BuildOptions::default().fallback_triangles),
                uv_offset: if m.has_uvs { uvs.len() as u32 } else { NO_UVS },
                _pad: 0,
            });
            clusters.extend_from_slice(&m.clusters);
            groups.extend_from_slice(&m.groups);
            bvh.extend_from_slice(&m.bvh);
            vertices.extend(m.vertices.iter().map(|v| GpuVertex {
                position: v.position,
                normal: v.normal,
            }));
            if m.has_uvs {
                uvs.extend(m.vertices.iter().map(|v| v.uv));
            }
            refs.extend_from_slice(&m.vertex_refs);
            tris.extend_from_slice(&m.triangles);
        }
        while !tris.len().is_multiple_of(4) {
            tris.push(0);
        }
        if clusters.len() as u64 >= (1 << 31)
            || tris.len() as u64 >= u32::MAX as u64
            || uvs.len() as u64 >= NO_UVS as u64
        {
            return Err(GpuError::Other(
                "scene geometry exceeds 32-bit offsets".into(),
            ));
        }
        // Direct visible-list slots: each instance owns a range as long as its mesh's cluster count.
        let mut next = 0u64;
        let instances: Vec<InstanceVgeo> = placements
            .iter()
            .map(|p| {
                let mut inst = instance_gpu(p);
                inst.visible_base = next.min(u32::MAX as u64) as u32;
                next += built[p.mesh as usize].borrow().clusters.len() as u64;
                inst
            })
            .collect();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let up = |name: &str, bytes: &[u8]| Buffer::with_data(ctx, name, bytes, usage);
        Ok(Self {
            meshes: up("scene meshes", bytemuck::cast_slice(&table))?,
            instances: up("scene instances", bytemuck::cast_slice(&instances))?,
            clusters: up("scene clusters", bytemuck::cast_slice(&clusters))?,
            groups: up("scene groups", bytemuck::cast_slice(&groups))?,
            bvh: up("scene bvh", bytemuck::cast_slice(&bvh))?,
            vertices: up("scene vertices", bytemuck::cast_slice(&vertices))?,
            // One word where no mesh has UVs: a binding needs a buffer.
            uvs: up(
                "scene uvs",
                bytemuck::cast_slice(if uvs.is_empty() { &[0u32][..] } else { &uvs }),
            )?,
            vertex_refs: up("scene vertex refs", bytemuck::cast_slice(&refs))?,
            triangles: up("scene triangles", &tris)?,
            total_clusters: clusters.len() as u32,
            instance_clusters: next,
            mesh_table: table,
            instance_count: placements.len() as u32,
        })
    }

    /// The descriptors every pass that decodes clusters binds, in this order: instances, meshes,
    /// clusters, vertices, vertex references, triangles (see `shaders_glsl/common/raster.glsl`).
    pub fn geometry_descs(&self) -> [Desc<'_>; 6] {
        [
            Desc::Storage(&self.instances),
            Desc::Storage(&self.meshes),
            Desc::Storage(&self.clusters),
            Desc::Storage(&self.vertices),
            Desc::Storage(&self.vertex_refs),
            Desc::Storage(&self.triangles),
        ]
    }

    /// GPU bytes of geometry (clusters, groups, BVH, vertices, references, triangles).
    pub fn geometry_bytes(&self) -> u64 {
        [
            &self.clusters,
            &self.groups,
            &self.bvh,
            &self.vertices,
            &self.uvs,
            &self.vertex_refs,
            &self.triangles,
        ]
        .iter()
        .map(|b| b.size())
        .sum()
    }
}
