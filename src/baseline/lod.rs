//! Pass `lod`: the discrete-LOD baseline, what engines do without virtualized geometry.
//!
//! Per mesh, [`LOD_COUNT`] levels made with meshoptimizer's simplifier (the one the builder uses):
//! [`LOD_FRACTIONS`] of the triangles, each simplified from the full mesh, with the object-space
//! error meshoptimizer reports (absolute; position and attributes with the builder's weights, so
//! a level's error is measured as a DAG cluster's is). All levels of a mesh share one vertex buffer and one index
//! buffer (per-level index ranges). Per instance and frame the coarsest level whose error
//! projected at the instance's bounding sphere ([`lod_error_px`], the cut's formula; weighted for
//! a small instance as vgeo weighs it, [`select_lod`]) stays within `error_px * lod_bias` pixels
//! is drawn, with the `brute` pipeline and shading so images compare.
//!
//! Two ways to pick and draw ([`LodSelection`]):
//! - `lod` ([`LodSelection::Gpu`], the default), GPU-driven as engines without virtual geometry
//!   do: pass `lod_cull` ([`super::lod_cull`]) tests each instance against the frustum and, with
//!   [`LodOptions::occlusion_cull`], the HZB in two phases (main: the previous frame's HZB,
//!   reprojected; draw; `depth_pyramid` from this frame's depth; post: the rejected ones against
//!   it; draw those), picks its level and appends it to its (mesh, level) bucket; then per mesh one
//!   `vkCmdDrawIndexedIndirectCount` draws the non-empty buckets. The HZB history lives in the
//!   renderer: a frame tests against the last frame it rendered at the same size.
//! - `lod-cpu` ([`LodSelection::Cpu`]): the same selection and frustum test on the CPU, one
//!   instanced `vkCmdDrawIndexed` per non-empty (mesh, level): what selection costs the CPU.

use glam::{DMat4, DVec3, Mat4, Vec3, Vec4};
use rayon::prelude::*;

use super::brute::{Classic, ClassicFrame, ClassicMesh, Draw, check_placements, instance_gpu};
use crate::builder::cut::{lod_error_px, proj_scale, small_instance_weight, weighted_error};
use crate::camera::Camera;
use crate::gpu::{Context, GpuError, GpuResult};
use crate::material::ShadeMode;
use crate::mesh::Mesh;
use crate::render::{Frame, Light, Placement};
use crate::shared::{InstanceGpu, LOD_LEVELS};

mod gpu;

use gpu::GpuLod;

/// Bucket of an instance culled by the frustum.
const CULLED: u32 = u32::MAX;

/// Levels per mesh: a full chain, each level half the previous one, down to 1/128 (0.8 %) of the
/// triangles, as engines build LOD chains (a level is not made below [`LOD_MIN_TRIANGLES`]).
pub const LOD_COUNT: usize = LOD_LEVELS as usize;

/// Share of the full mesh's triangles each level aims for: halving.
pub const LOD_FRACTIONS: [f32; LOD_COUNT] =
    [1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625, 0.0078125];

/// A level is not simplified further once the previous one has this many triangles or fewer
/// (the rest of the chain shares it): smaller levels save nothing a draw call would notice.
pub const LOD_MIN_TRIANGLES: usize = 64;

/// Where the discrete-LOD path picks levels and culls.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LodSelection {
    /// Mode `lod`: on the GPU (`lod_cull`), drawn with multi-draw-indirect-count.
    #[default]
    Gpu,
    /// Mode `lod-cpu`: on the CPU, one instanced draw per non-empty (mesh, level).
    Cpu,
}

/// Options of the discrete-LOD path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodOptions {
    /// Factor on the pixel threshold: a level is fine while its projected error is at most
    /// `error_px * lod_bias` (larger: coarser levels sooner). The benchmark sweeps it.
    pub lod_bias: f32,
    /// Skip instances whose bounding sphere lies outside the view frustum (side and near planes),
    /// as engines do. Culled instances are not drawn and not counted in `Frame::triangles`; the
    /// image is the same either way.
    pub frustum_cull: bool,
    /// GPU selection only: skip instances whose bounding box lies behind the HZB (two phases, see
    /// the module's documentation). Occluded instances are not drawn and not counted in
    /// `Frame::triangles`; the image is the same either way.
    pub occlusion_cull: bool,
    /// GPU (`lod`) or CPU (`lod-cpu`) selection.
    pub selection: LodSelection,
}

impl Default for LodOptions {
    fn default() -> Self {
        Self {
            lod_bias: 1.0,
            frustum_cull: true,
            occlusion_cull: true,
            selection: LodSelection::Gpu,
        }
    }
}

impl LodOptions {
    /// The options of a mode name: `lod` (the defaults) or `lod-cpu`; `None` for another name.
    pub fn for_mode(mode: &str) -> Option<Self> {
        match mode {
            "lod" => Some(Self::default()),
            "lod-cpu" => Some(Self {
                selection: LodSelection::Cpu,
                ..Self::default()
            }),
            _ => None,
        }
    }
}

/// What a frame of the discrete-LOD path culled and drew (last frame of a call).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LodStats {
    /// Instances outside the frustum.
    pub frustum_culled: u32,
    /// Instances drawn by the main phase (all drawn ones with CPU selection).
    pub drawn_main: u32,
    /// Instances the previous frame's HZB rejected in the main phase, re-tested in the post phase.
    pub post_tested: u32,
    /// Of those, drawn by the post phase, and occluded for good.
    pub drawn_post: u32,
    pub occluded: u32,
    /// Instances drawn with the faces turned away culled (closed solids seen from outside; GPU
    /// selection only).
    pub cull_back: u32,
    /// Per placement: its level, `None` when outside the frustum (also for occluded ones).
    pub levels: Vec<Option<u8>>,
    /// Per placement: whether the post phase found it occluded (not drawn).
    pub occluded_instances: Vec<bool>,
}

impl LodStats {
    /// Instances drawn (both phases).
    pub fn drawn(&self) -> u32 {
        self.drawn_main + self.drawn_post
    }
}

/// The levels of one mesh on the CPU: what simplification produced and what selection needs.
#[derive(Clone, Debug, PartialEq)]
pub struct LodChain {
    /// Every level's triangles, concatenated (indices into the mesh's vertices).
    pub indices: Vec<u32>,
    /// Per level, `(first_index, index_count)` in `indices`. A level that could not be made smaller
    /// than the previous one shares its range (equal counts).
    pub ranges: [(u32, u32); LOD_COUNT],
    /// Per level, the object-space error (0 for level 0), non-decreasing.
    pub errors: [f32; LOD_COUNT],
    /// Per level, the coverage part of its error (at most it, non-decreasing): what a small
    /// instance counts whole ([`select_lod`]), as vgeo's groups' (`BuiltMesh::group_coverage`).
    pub coverages: [f32; LOD_COUNT],
    /// Object-space bounding sphere of the mesh: centre xyz, radius w.
    pub sphere: [f32; 4],
    /// Object-space bounding box of the mesh (min, max; zero when it has no vertex).
    pub bounds: [[f32; 3]; 2],
    /// The mesh is a closed solid ([`crate::builder::solid::closed_solid`]): the GPU selection
    /// draws an instance seen from outside its box with the faces turned away culled, as vgeo's
    /// hardware path drops them (docs/architecture.md, "Faces turned away").
    pub closed_solid: bool,
}

impl LodChain {
    /// Simplifies `mesh` into [`LOD_COUNT`] levels (deterministic).
    ///
    /// Level `k` targets `LOD_FRACTIONS[k]` of the triangles, simplified from the full mesh with no
    /// error limit (across attribute seams where keeping them leaves it 20 % over the target);
    /// once a level has at most [`LOD_MIN_TRIANGLES`], the rest share it. Its error is the larger
    /// of meshoptimizer's absolute error and the coverage error (`simplify::coverage_error`),
    /// raised to the previous level's error where smaller so errors never decrease. A level meshoptimizer cannot make smaller than
    /// the previous one, or only makes empty (tiny meshes), reuses the previous level: counts never
    /// grow and no level of a non-empty mesh is empty.
    pub fn build(mesh: &Mesh) -> Self {
        let full = &mesh.indices;
        let mut indices: Vec<u32> = full.clone();
        let mut ranges = [(0u32, full.len() as u32); LOD_COUNT];
        let mut errors = [0.0f32; LOD_COUNT];
        let mut coverages = [0.0f32; LOD_COUNT];
        // The builder's simplifier and error (position and attributes, same weights), so that a
        // level's error means what a DAG cluster's does and `--error-px 1` compares.
        let defaults = crate::builder::BuildOptions::default();
        let uv_of = |v: usize| mesh.uvs[v];
        let (values, weights) = crate::builder::simplify::attribute_values(
            mesh.positions.len(),
            &|v| mesh.normals[v],
            mesh.has_uvs
                .then_some(&uv_of as &(dyn Fn(usize) -> [f32; 2] + Sync)),
            defaults.normal_weight,
            defaults.uv_weight,
        );
        let attrs = crate::builder::simplify::Attributes {
            values: &values,
            stride: weights.len(),
            weights: &weights,
        };
        let tris: Vec<[u32; 3]> = full.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        for k in 1..LOD_COUNT {
            let prev = ranges[k - 1];
            if (prev.1 as usize / 3) <= LOD_MIN_TRIANGLES {
                ranges[k] = prev;
                errors[k] = errors[k - 1];
                coverages[k] = coverages[k - 1];
                continue;
            }
            let tri_target = (full.len() / 3) as f32 * LOD_FRACTIONS[k];
            let target = (tri_target.round() as usize).max(1);
            let lod = (!tris.is_empty()).then(|| {
                let run = |mode| {
                    crate::builder::simplify::simplify(
                        &tris,
                        &mesh.positions,
                        crate::builder::simplify::Pieces::ByPosition,
                        Some(&attrs),
                        &|_| false,
                        target,
                        f32::MAX,
                        mode,
                    )
                };
                let mut out = run(crate::builder::simplify::Mode::Locked);
                // Attribute seams (creases, UV and material borders) can stop the halving of
                // the coarse levels; there the chain collapses across them, as the builder's
                // groups do when they cannot shrink otherwise (the error says what it cost).
                if out.tris.len() > target + target / 5 {
                    let p = run(crate::builder::simplify::Mode::Permissive);
                    if !p.tris.is_empty() && p.tris.len() < out.tris.len() {
                        out = p;
                    }
                }
                // Each level is simplified from the full mesh: both errors are against it.
                let err = (out.combined(), out.coverage);
                (out.tris.into_iter().flatten().collect::<Vec<u32>>(), err)
            });
            match lod {
                // Smaller but not empty: meshoptimizer may collapse a tiny closed mesh to nothing,
                // and an instance must never vanish because it is far.
                Some((out, (err, cov))) if !out.is_empty() && (out.len() as u32) < prev.1 => {
                    ranges[k] = (indices.len() as u32, out.len() as u32);
                    errors[k] = err.max(errors[k - 1]);
                    coverages[k] = cov.max(coverages[k - 1]).min(errors[k]);
                    indices.extend_from_slice(&out);
                }
                _ => {
                    ranges[k] = prev;
                    errors[k] = errors[k - 1];
                    coverages[k] = coverages[k - 1];
                }
            }
        }
        Self {
            indices,
            ranges,
            errors,
            coverages,
            sphere: bounding_sphere(mesh),
            bounds: mesh.bounds().map_or([[0.0; 3]; 2], |(lo, hi)| [lo, hi]),
            closed_solid: crate::builder::solid::closed_solid(&mesh.positions, &mesh.indices),
        }
    }

    /// Triangles per level.
    pub fn triangle_counts(&self) -> [u32; LOD_COUNT] {
        self.ranges.map(|(_, n)| n / 3)
    }
}

/// A sphere around every vertex: the bounding box's centre and the farthest vertex from it.
fn bounding_sphere(mesh: &Mesh) -> [f32; 4] {
    let Some((lo, hi)) = mesh.bounds() else {
        return [0.0; 4];
    };
    let c = (Vec3::from(lo) + Vec3::from(hi)) * 0.5;
    let r2 = mesh
        .positions
        .iter()
        .map(|p| (Vec3::from(*p) - c).length_squared())
        .fold(0.0f32, f32::max);
    // A hair larger so f32 rounding never leaves a vertex outside.
    [c.x, c.y, c.z, r2.sqrt() * (1.0 + 1e-6)]
}

/// What selection needs of one mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
struct LodInfo {
    ranges: [(u32, u32); LOD_COUNT],
    errors: [f32; LOD_COUNT],
    coverages: [f32; LOD_COUNT],
    sphere: [f32; 4],
    bounds: [[f32; 3]; 2],
    closed_solid: bool,
}

/// `sphere` (object space) placed by `transform`, relative to `camera_pos`: (camera-relative
/// centre, radius, largest axis scale of the transform).
fn world_sphere(sphere: &[f32; 4], transform: &DMat4, camera_pos: DVec3) -> (Vec3, f32, f32) {
    let center = transform.transform_point3(DVec3::new(
        sphere[0] as f64,
        sphere[1] as f64,
        sphere[2] as f64,
    ));
    let scale = crate::render::max_axis_scale(transform);
    ((center - camera_pos).as_vec3(), sphere[3] * scale, scale)
}

/// The level of an instance of a mesh with per-level `errors` (and their coverage parts,
/// `coverages`) and object-space bounding `sphere`, placed by `transform`, seen from `camera_pos`
/// (world), for threshold `tau` pixels: the coarsest level whose error, scaled by the transform's
/// largest axis scale, projects to at most `tau` at the nearest point of the transformed sphere
/// ([`lod_error_px`]). An instance whose sphere projects under `SMALL_WEIGHT_RADIUS_PX` counts a
/// share of each error ([`small_instance_weight`]) and its coverage part whole, as vgeo weighs a
/// small instance's (`common/lod.glsl`'s `weighted_error`). Level 0 when `tau <= 0` (or NaN), so a
/// zero threshold always draws full detail. Monotonic: a farther instance never gets a finer
/// level (errors and coverages are non-decreasing, and the weight only falls with distance).
pub fn select_lod(
    errors: &[f32; LOD_COUNT],
    coverages: &[f32; LOD_COUNT],
    sphere: &[f32; 4],
    transform: &DMat4,
    camera_pos: DVec3,
    proj_scale: f32,
    tau: f32,
) -> u8 {
    let (rel, radius, scale) = world_sphere(sphere, transform, camera_pos);
    level_for(errors, coverages, rel, radius, scale, proj_scale, tau)
}

fn level_for(
    errors: &[f32; LOD_COUNT],
    coverages: &[f32; LOD_COUNT],
    rel: Vec3,
    radius: f32,
    scale: f32,
    proj_scale: f32,
    tau: f32,
) -> u8 {
    if tau.is_nan() || tau <= 0.0 {
        return 0;
    }
    let w = small_instance_weight(lod_error_px(radius, rel, radius, Vec3::ZERO, proj_scale));
    for k in (1..LOD_COUNT).rev() {
        let e = weighted_error(errors[k], coverages[k], w);
        if lod_error_px(e * scale, rel, radius, Vec3::ZERO, proj_scale) <= tau {
            return k as u8;
        }
    }
    0
}

/// The side and near planes of a camera-relative `view_proj` (reverse-Z, infinite far), as
/// `(normal, d)` with `dot(normal, p) + d >= 0` inside and unit normals.
fn frustum_planes(view_proj: &Mat4) -> [Vec4; 5] {
    let r = [
        view_proj.row(0),
        view_proj.row(1),
        view_proj.row(2),
        view_proj.row(3),
    ];
    // x >= -w, x <= w, y >= -w, y <= w, z <= w (reverse-Z: depth 1 at the near plane).
    [
        r[3] + r[0],
        r[3] - r[0],
        r[3] + r[1],
        r[3] - r[1],
        r[3] - r[2],
    ]
    .map(|p| {
        let n = p.truncate().length();
        if n > 0.0 { p / n } else { p }
    })
}

/// Whether a camera-relative sphere lies entirely outside one of `planes`.
fn outside(planes: &[Vec4; 5], center: Vec3, radius: f32) -> bool {
    planes
        .iter()
        .any(|p| p.truncate().dot(center) + p.w < -radius)
}

/// The discrete-LOD renderer: the classic pipeline plus every mesh's levels on the GPU.
pub struct Lod {
    classic: Classic,
    infos: Vec<LodInfo>,
    opts: LodOptions,
    gpu: Option<GpuLod>,
}

impl Lod {
    /// Splits every mesh's vertices per material (material borders become seams the simplifier
    /// keeps), simplifies it into its levels (in parallel), uploads them with the scene's
    /// materials and creates the pipelines.
    /// `meshes` may hold the meshes or references to them (anything that borrows as one).
    pub fn new<M: std::borrow::Borrow<Mesh> + Sync>(
        ctx: &Context,
        meshes: &[M],
        opts: &LodOptions,
    ) -> GpuResult<Self> {
        let split: Vec<ClassicMesh> = meshes
            .par_iter()
            .map(|m| ClassicMesh::new(m.borrow()))
            .collect();
        let chains: Vec<LodChain> = split.par_iter().map(|m| LodChain::build(&m.mesh)).collect();
        let indices: Vec<Option<&[u32]>> = chains.iter().map(|c| Some(&c.indices[..])).collect();
        let on_gpu = opts.selection == LodSelection::Gpu;
        let classic = Classic::new(ctx, "lod", &split, &indices, on_gpu)?;
        let infos: Vec<LodInfo> = chains
            .iter()
            .map(|c| LodInfo {
                ranges: c.ranges,
                errors: c.errors,
                coverages: c.coverages,
                sphere: c.sphere,
                bounds: c.bounds,
                closed_solid: c.closed_solid,
            })
            .collect();
        let gpu = if on_gpu {
            Some(GpuLod::new(ctx, &infos)?)
        } else {
            None
        };
        Ok(Self {
            classic,
            infos,
            opts: *opts,
            gpu,
        })
    }

    /// Forgets the HZB of the frames rendered so far (GPU selection): the next frame draws every
    /// instance in the frustum in its main phase.
    pub fn reset_history(&self) {
        if let Some(g) = &self.gpu {
            g.reset_history();
        }
    }

    /// The options this renderer was made with.
    pub fn options(&self) -> &LodOptions {
        &self.opts
    }

    /// Triangles of each level of mesh `mesh` (an index into the meshes given to [`Lod::new`];
    /// panics when out of range).
    pub fn lod_triangle_counts(&self, mesh: usize) -> [u32; LOD_COUNT] {
        self.infos[mesh].ranges.map(|(_, n)| n / 3)
    }

    /// Object-space error of each level of mesh `mesh` (non-decreasing, 0 for level 0; panics
    /// when out of range).
    pub fn lod_errors(&self, mesh: usize) -> [f32; LOD_COUNT] {
        self.infos[mesh].errors
    }

    /// GPU bytes of geometry (all levels).
    pub fn geometry_bytes(&self) -> u64 {
        self.classic.geometry_bytes()
    }

    /// GPU bytes per frame for `instances` instances: their records, and with GPU selection the
    /// mesh index, instance-list regions (one per level), post list and level of each.
    pub fn instance_bytes(&self, instances: usize) -> u64 {
        let per = size_of::<InstanceGpu>()
            + if self.gpu.is_some() {
                4 * (LOD_COUNT + 3)
            } else {
                0
            };
        (instances * per) as u64
    }

    /// Warnings about the materials (unreadable textures), each naming its file and material.
    pub fn warnings(&self) -> &[String] {
        self.classic.warnings()
    }

    /// The level each placement gets when rendered from `camera` into an image `height` pixels
    /// high at threshold `error_px` (times the options' `lod_bias`), in placement order. Frustum
    /// culling is not applied here: a culled instance still reports the level it would get.
    pub fn selection(
        &self,
        placements: &[Placement],
        camera: &Camera,
        height: u32,
        error_px: f32,
    ) -> GpuResult<Vec<u8>> {
        check_placements(placements, self.infos.len())?;
        let (ps, tau) = self.threshold(camera, height, error_px);
        Ok(placements
            .iter()
            .map(|p| self.select(p, camera, ps, tau))
            .collect())
    }

    fn threshold(&self, camera: &Camera, height: u32, error_px: f32) -> (f32, f32) {
        let tau = error_px * self.opts.lod_bias;
        (
            proj_scale(height as f32, camera.fov_y),
            if tau.is_nan() { 0.0 } else { tau },
        )
    }

    fn select(&self, p: &Placement, camera: &Camera, ps: f32, tau: f32) -> u8 {
        let info = &self.infos[p.mesh as usize];
        select_lod(
            &info.errors,
            &info.coverages,
            &info.sphere,
            &p.transform,
            camera.position,
            ps,
            tau,
        )
    }

    /// Renders `placements` seen from `camera` into a `width` x `height` lit frame at threshold
    /// `error_px` and reads it back. `Frame::triangles` counts the triangles drawn (selected
    /// levels times instances not culled).
    pub fn render(
        &self,
        placements: &[Placement],
        camera: &Camera,
        light: &Light,
        width: u32,
        height: u32,
        error_px: f32,
    ) -> GpuResult<Frame> {
        self.render_view(
            placements,
            camera,
            light,
            (width, height),
            error_px,
            ShadeMode::Lit,
        )
    }

    /// [`Lod::render`] with `shade` drawing `mode` (lit, albedo, normals or materials).
    pub fn render_view(
        &self,
        placements: &[Placement],
        camera: &Camera,
        light: &Light,
        size: (u32, u32),
        error_px: f32,
        mode: ShadeMode,
    ) -> GpuResult<Frame> {
        self.render_with_stats(placements, camera, light, size, error_px, mode)
            .map(|(frame, _)| frame)
    }

    /// [`Lod::render_view`] with what the frame culled and drew.
    pub fn render_with_stats(
        &self,
        placements: &[Placement],
        camera: &Camera,
        light: &Light,
        (width, height): (u32, u32),
        error_px: f32,
        mode: ShadeMode,
    ) -> GpuResult<(Frame, LodStats)> {
        if let Some(g) = &self.gpu {
            let mut out = self.gpu_frames(
                g,
                placements,
                std::slice::from_ref(camera),
                light,
                (width, height),
                error_px,
                mode,
                true,
            )?;
            let stats = out.1.take().unwrap_or_default();
            return out
                .0
                .pop()
                .map(|f| (f, stats))
                .ok_or_else(|| GpuError::Other("no frame rendered".into()));
        }
        let (f, stats) = self.frame_input(placements, camera, (width, height), error_px)?;
        let frame = self.classic.render_draws(
            &f.instances,
            &f.draws,
            camera,
            light,
            width,
            height,
            mode,
            true,
        )?;
        Ok((frame, stats))
    }

    /// The frames of `cameras` (a camera path) at threshold `error_px` in one submission, back
    /// to back, without read-back: the GPU times per pass of each frame (the benchmark times
    /// paths this way). With GPU selection and occlusion culling each frame tests against the
    /// previous one's HZB; with CPU selection all frames are selected before the submission.
    pub fn render_path_timed(
        &self,
        placements: &[Placement],
        cameras: &[Camera],
        light: &Light,
        size: (u32, u32),
        error_px: f32,
    ) -> GpuResult<Vec<Vec<(String, f64)>>> {
        if let Some(g) = &self.gpu {
            let (frames, _) = self.gpu_frames(
                g,
                placements,
                cameras,
                light,
                size,
                error_px,
                ShadeMode::Lit,
                false,
            )?;
            return Ok(frames.into_iter().map(|f| f.gpu_ms).collect());
        }
        let frames = cameras
            .iter()
            .map(|c| Ok(self.frame_input(placements, c, size, error_px)?.0))
            .collect::<GpuResult<Vec<_>>>()?;
        self.classic.path_times(&frames, light, size)
    }

    /// Per-instance level selection and frustum culling for `camera` on the CPU: instances
    /// grouped per (mesh, level), one instanced draw each; with the levels picked.
    fn frame_input(
        &self,
        placements: &[Placement],
        camera: &Camera,
        (width, height): (u32, u32),
        error_px: f32,
    ) -> GpuResult<(ClassicFrame, LodStats)> {
        check_placements(placements, self.infos.len())?;
        let (ps, tau) = self.threshold(camera, height, error_px);
        // Counting sort by (mesh, level): O(instances + meshes), allocations per frame only.
        let buckets = self.infos.len() * LOD_COUNT;
        let planes = frustum_planes(&camera.view_proj(width, height));
        let mut selected = Vec::with_capacity(placements.len());
        let mut counts = vec![0u32; buckets];
        for p in placements {
            let info = &self.infos[p.mesh as usize];
            let (rel, radius, scale) = world_sphere(&info.sphere, &p.transform, camera.position);
            if self.opts.frustum_cull && outside(&planes, rel, radius) {
                selected.push(CULLED);
                continue;
            }
            let level = level_for(&info.errors, &info.coverages, rel, radius, scale, ps, tau);
            let b = p.mesh as usize * LOD_COUNT + level as usize;
            counts[b] += 1;
            selected.push(b as u32);
        }
        let mut cursor = Vec::with_capacity(buckets);
        let mut draws = Vec::new();
        let mut first = 0u32;
        for (b, &n) in counts.iter().enumerate() {
            cursor.push(first);
            if n > 0 {
                let mesh = b / LOD_COUNT;
                let (first_index, index_count) = self.infos[mesh].ranges[b % LOD_COUNT];
                draws.push(Draw {
                    mesh: mesh as u32,
                    first_index,
                    index_count,
                    first_instance: first,
                    instance_count: n,
                });
            }
            first += n;
        }
        let mut instances = vec![bytemuck::Zeroable::zeroed(); first as usize];
        for (p, &b) in placements.iter().zip(&selected) {
            if b == CULLED {
                continue;
            }
            let slot = &mut cursor[b as usize];
            instances[*slot as usize] = instance_gpu(camera, p);
            *slot += 1;
        }
        let instances: Vec<InstanceGpu> = instances;
        let levels: Vec<Option<u8>> = selected
            .iter()
            .map(|&b| (b != CULLED).then_some((b as usize % LOD_COUNT) as u8))
            .collect();
        let stats = LodStats {
            frustum_culled: levels.iter().filter(|l| l.is_none()).count() as u32,
            drawn_main: instances.len() as u32,
            occluded_instances: vec![false; levels.len()],
            levels,
            ..Default::default()
        };
        Ok((
            ClassicFrame {
                instances,
                draws,
                camera: *camera,
                view_proj: None,
            },
            stats,
        ))
    }
}
