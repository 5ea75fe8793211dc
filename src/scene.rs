//! Scene files (TOML): meshes, instances (explicit or procedural), camera and light.
//!
//! Paths are relative to the scene file. Every table rejects unknown keys. Numbers may be written as
//! integers or floats; all must be finite. The whole file may produce at most [`MAX_INSTANCES`]
//! instances.
//!
//! ```toml
//! # Meshes: a name and a file (any importable mesh, or a built .vgeo file).
//! [[mesh]]
//! name = "bunny"
//! path = "../bunny.ply"
//!
//! [[mesh]]
//! name = "spot"
//! path = "../spot.obj"
//! materials = 64                  # optional: replace its materials by 64 generated ones, each a
//!                                 # patch of the surface (material-cost benchmarks)
//!
//! # One instance. All keys but `mesh` are optional.
//! [[instance]]
//! mesh = "bunny"
//! translation = [0, 0, 0]         # f64, so scenes may sit far from the origin
//! rotation_deg = [0, 90, 0]       # Euler angles in degrees, applied about the fixed X, then Y, then Z axes
//! # axis_angle = [0, 1, 0, 90]    # or: axis x, y, z and angle in degrees (not both)
//! scale = 6                       # a number or [x, y, z]; non-zero (negative mirrors)
//! color = [1.0, 0.8, 0.6]         # tint, default [1, 1, 1]
//!
//! # A grid of nx * ny * nz instances at origin + (i dx, j dy, k dz).
//! [[grid]]
//! mesh = "spot"
//! count = [10, 1, 10]             # every count >= 1
//! spacing = [2.0, 0, 2.0]
//! origin = [-9, 0, -9]            # default [0, 0, 0]
//! jitter = [0.3, 0, 0.3]          # random offset in [-j, j] per axis (a number: all axes), default 0
//! random_rotation = true          # random rotation about the Y (up) axis, default false
//! seed = 7                        # for jitter and rotation, default 0
//! # rotation_deg / axis_angle, scale and color as for [[instance]], applied to every instance
//!
//! # `count` instances at uniformly random positions in the box [min, max].
//! [[scatter]]
//! mesh = "bunny"
//! count = 50
//! seed = 1                        # default 0; the same seed gives the same instances
//! min = [-10, 0, -10]
//! max = [10, 0, 10]
//! scale_range = [4, 8]            # uniform scale drawn in [a, b], default [1, 1]
//! random_yaw = true               # random rotation about Y, default true
//! # rotation_deg / axis_angle and color as for [[instance]]
//!
//! # Omitted: the camera frames the bounds of all instances.
//! [camera]
//! eye = [0, 3, 12]
//! target = [0, 0, 0]
//! up = [0, 1, 0]                  # default [0, 1, 0]
//! fov_y_deg = 45                  # vertical field of view, default 45
//! near = 0.05                     # default: from the eye's distance to the scene's bounds
//!
//! [light]
//! direction = [0.4, 1.0, 0.6]     # towards the light, default [0.4, 1.0, 0.6]
//!
//! # Optional camera path (benchmarks fly it): keyframes, linearly interpolated. Up, field of view
//! # and near plane are the [camera]'s (or its defaults).
//! [[path]]
//! eye = [0, 3, 12]
//! target = [0, 0, 0]
//! [[path]]
//! eye = [4, 2, 6]
//! target = [0, 0.5, 0]
//! ```
//!
//! A mesh path `generated:NAME` names a mesh made in code ([`generated::generated_mesh`]); it is
//! kept as written, not resolved against the scene's folder. Scenes' meshes are loaded and built
//! through [`load`] ([`load::LoadedScene`], [`load::MeshCache`]), the one path every command uses.
//!
//! Rotations: `rotation_deg = [x, y, z]` is `R = Rz(z) * Ry(y) * Rx(x)` (Blender's "XYZ Euler").
//! An instance's transform is `translate * rotate * scale`; for procedural entries the random yaw
//! is applied after the entry's own rotation.

pub mod generated;
pub mod load;

use std::fmt;
use std::path::{Path, PathBuf};

use glam::{DMat3, DMat4, DQuat, DVec3, Vec3};
use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};

use crate::camera::Camera;

/// Most instances one scene file may produce.
pub const MAX_INSTANCES: u64 = 100_000_000;
/// Default direction towards the light (normalized on use).
pub const DEFAULT_LIGHT_DIR: [f32; 3] = [0.4, 1.0, 0.6];

/// An error loading a scene file; every message names the file, and the entry where there is one.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{}: cannot read the scene file: {source}", path.display())]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Not valid TOML, or not the scene format (unknown key, wrong type, missing key).
    #[error("{}: {message}", path.display())]
    Parse {
        /// The scene file.
        path: PathBuf,
        /// The parser's message, with line and column.
        message: String,
    },
    /// Well-formed but invalid content.
    #[error("{}: {entry}: {message}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// The entry at fault, e.g. `grid #2 (mesh "bunny")` or `[camera]`.
        entry: String,
        /// What is wrong with it.
        message: String,
    },
}

/// A mesh a scene uses.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneMesh {
    /// The name instances refer to it by.
    pub name: String,
    /// Resolved against the scene file's folder.
    pub path: PathBuf,
    /// Replace the mesh's materials by this many generated ones
    /// ([`crate::mesh::assign_patch_materials`]); for material-cost benchmarks.
    pub materials: Option<u32>,
}

/// One placed copy of a mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// Index into [`Scene::meshes`].
    pub mesh: u32,
    /// Model to world, in f64.
    pub transform: DMat4,
    /// Colour tint.
    pub color: [f32; 3],
}

/// An explicit camera from the scene file.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    /// Camera position, world space.
    pub eye: DVec3,
    /// The point looked at, world space (differs from `eye`).
    pub target: DVec3,
    /// Up hint, unit length.
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_deg: f32,
    /// `None`: chosen from the distance between the eye and the scene's bounds.
    pub near: Option<f32>,
}

/// A keyframe of a scene's camera path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathKey {
    /// Camera position, world space.
    pub eye: DVec3,
    /// The point looked at, world space (differs from `eye`).
    pub target: DVec3,
}

/// Prefix of mesh paths that name a mesh generated in code.
pub const GENERATED_PREFIX: &str = "generated:";

/// A loaded, validated scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Meshes, in file order; instances index into this.
    pub meshes: Vec<SceneMesh>,
    /// All instances: `[[instance]]` entries, then grids, then scatters, each in file order.
    pub instances: Vec<Instance>,
    /// `None`: frame the scene's bounds (see [`Scene::camera`]).
    pub camera: Option<CameraDesc>,
    /// Unit direction towards the light, world space.
    pub light_dir: Vec3,
    /// Camera path keyframes (`[[path]]`), in file order; empty when the file has none.
    pub path: Vec<PathKey>,
}

impl Scene {
    /// Reads, parses and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, path)
    }

    /// Parses and validates scene text; `path` names the file in errors and is the base of relative
    /// mesh paths (its folder).
    pub fn parse(text: &str, path: &Path) -> Result<Scene, SceneError> {
        let file: SceneFile = toml::from_str(text).map_err(|e| SceneError::Parse {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        let base = path.parent().unwrap_or(Path::new(""));
        build(file, base).map_err(|(entry, message)| SceneError::Invalid {
            path: path.to_path_buf(),
            entry,
            message,
        })
    }

    /// One instance of one mesh file with the identity transform, no explicit camera.
    pub fn single_mesh(path: &Path) -> Scene {
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "mesh".into());
        Scene {
            meshes: vec![SceneMesh {
                name,
                path: path.to_path_buf(),
                materials: None,
            }],
            instances: vec![Instance {
                mesh: 0,
                transform: DMat4::IDENTITY,
                color: [1.0; 3],
            }],
            camera: None,
            light_dir: Vec3::from(DEFAULT_LIGHT_DIR).normalize(),
            path: Vec::new(),
        }
    }

    /// World bounds of all instances, from each mesh's object-space box (`mesh_bounds[i]` for
    /// `meshes[i]`; instances of meshes without an entry are left out). `None` if nothing is left.
    pub fn bounds(&self, mesh_bounds: &[([f32; 3], [f32; 3])]) -> Option<(DVec3, DVec3)> {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for inst in &self.instances {
            let Some(&(blo, bhi)) = mesh_bounds.get(inst.mesh as usize) else {
                continue;
            };
            let (blo, bhi) = (Vec3::from(blo).as_dvec3(), Vec3::from(bhi).as_dvec3());
            let centre = inst.transform.transform_point3((blo + bhi) * 0.5);
            let half = (bhi - blo) * 0.5;
            let m = DMat3::from_mat4(inst.transform);
            let ext = m.x_axis.abs() * half.x + m.y_axis.abs() * half.y + m.z_axis.abs() * half.z;
            lo = lo.min(centre - ext);
            hi = hi.max(centre + ext);
        }
        (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
    }

    /// The camera: the explicit one, or [`Camera::frame_bounds`] over all instances' boxes (see
    /// [`Scene::bounds`]; a unit box at the origin when there are none).
    pub fn camera(&self, mesh_bounds: &[([f32; 3], [f32; 3])], aspect: f32) -> Camera {
        let bounds = self.bounds(mesh_bounds);
        match &self.camera {
            Some(c) => {
                let near = c.near.unwrap_or_else(|| auto_near(c.eye, bounds));
                Camera::look_at(c.eye, c.target, c.up, c.fov_y_deg.to_radians(), near)
            }
            None => {
                let (lo, hi) = bounds.unwrap_or((DVec3::splat(-1.0), DVec3::splat(1.0)));
                Camera::frame_bounds(lo, hi, aspect)
            }
        }
    }
}

impl Scene {
    /// A camera at `eye` looking at `target` with the explicit camera's up, field of view and near
    /// plane (defaults: +Y, 45 degrees, near from the eye's distance to the scene's bounds).
    pub fn camera_at(
        &self,
        eye: DVec3,
        target: DVec3,
        mesh_bounds: &[([f32; 3], [f32; 3])],
    ) -> Camera {
        let (up, fov, near) = match &self.camera {
            Some(c) => (c.up, c.fov_y_deg, c.near),
            None => (Vec3::Y, 45.0, None),
        };
        let near = near.unwrap_or_else(|| auto_near(eye, self.bounds(mesh_bounds)));
        Camera::look_at(eye, target, up, fov.to_radians(), near)
    }

    /// `frames` cameras along the path: keyframes linearly interpolated at evenly spaced parameters,
    /// the first and last frames on the first and last keyframes (one frame: the first keyframe).
    /// Without a path: [`Scene::camera`] repeated.
    pub fn path_cameras(
        &self,
        mesh_bounds: &[([f32; 3], [f32; 3])],
        aspect: f32,
        frames: u32,
    ) -> Vec<Camera> {
        if self.path.is_empty() {
            return vec![self.camera(mesh_bounds, aspect); frames as usize];
        }
        interpolate_path(&self.path, frames)
            .into_iter()
            .map(|k| self.camera_at(k.eye, k.target, mesh_bounds))
            .collect()
    }
}

/// `frames` keys along `keys` (non-empty), linearly interpolated at evenly spaced parameters from the
/// first key to the last.
pub fn interpolate_path(keys: &[PathKey], frames: u32) -> Vec<PathKey> {
    let Some(first) = keys.first() else {
        return Vec::new();
    };
    let segments = (keys.len() - 1) as f64;
    (0..frames)
        .map(|i| {
            if frames <= 1 || segments == 0.0 {
                return *first;
            }
            let t = i as f64 / (frames - 1) as f64 * segments;
            let k = (t.floor() as usize).min(keys.len() - 2);
            let f = t - k as f64;
            let (a, b) = (keys[k], keys[k + 1]);
            let eye = a.eye.lerp(b.eye, f);
            let mut target = a.target.lerp(b.target, f);
            if target == eye {
                // Cannot look at itself: keep the direction of the segment's start.
                target = eye + (a.target - a.eye);
            }
            PathKey { eye, target }
        })
        .collect()
}

/// Near plane for an explicit camera without one: half the distance from the eye to the scene's box,
/// at least 1e-4 of the box's radius.
fn auto_near(eye: DVec3, bounds: Option<(DVec3, DVec3)>) -> f32 {
    let Some((lo, hi)) = bounds else { return 0.01 };
    let radius = (hi - lo).length() * 0.5;
    let dist = (eye.clamp(lo, hi) - eye).length();
    let near = (dist * 0.5).max(radius * 1e-4) as f32;
    if near.is_finite() && near > 0.0 {
        near
    } else {
        0.01
    }
}

// ---------------------------------------------------------------------------------------------
// File format (serde) and validation.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    #[serde(default)]
    mesh: Vec<MeshEntry>,
    #[serde(default)]
    instance: Vec<InstanceEntry>,
    #[serde(default)]
    grid: Vec<GridEntry>,
    #[serde(default)]
    scatter: Vec<ScatterEntry>,
    camera: Option<CameraEntry>,
    light: Option<LightEntry>,
    #[serde(default)]
    path: Vec<PathEntry>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PathEntry {
    eye: [f64; 3],
    target: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshEntry {
    name: String,
    path: PathBuf,
    materials: Option<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct InstanceEntry {
    mesh: String,
    #[serde(default)]
    translation: [f64; 3],
    rotation_deg: Option<[f64; 3]>,
    axis_angle: Option<[f64; 4]>,
    scale: Option<Scale>,
    color: Option<[f64; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GridEntry {
    mesh: String,
    count: [i64; 3],
    spacing: [f64; 3],
    #[serde(default)]
    origin: [f64; 3],
    jitter: Option<Scale>,
    #[serde(default)]
    random_rotation: bool,
    #[serde(default)]
    seed: u64,
    rotation_deg: Option<[f64; 3]>,
    axis_angle: Option<[f64; 4]>,
    scale: Option<Scale>,
    color: Option<[f64; 3]>,
}

fn default_true() -> bool {
    true
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ScatterEntry {
    mesh: String,
    count: i64,
    #[serde(default)]
    seed: u64,
    min: [f64; 3],
    max: [f64; 3],
    scale_range: Option<[f64; 2]>,
    #[serde(default = "default_true")]
    random_yaw: bool,
    rotation_deg: Option<[f64; 3]>,
    axis_angle: Option<[f64; 4]>,
    color: Option<[f64; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraEntry {
    eye: [f64; 3],
    target: [f64; 3],
    up: Option<[f64; 3]>,
    fov_y_deg: Option<f64>,
    near: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightEntry {
    direction: [f64; 3],
}

/// A number for all three axes or `[x, y, z]`: `scale = 2`, `scale = [1, 2, 1]`.
struct Scale([f64; 3]);

impl<'de> Deserialize<'de> for Scale {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Scale;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an array of 3 numbers")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Scale, E> {
                Ok(Scale([v; 3]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Scale, E> {
                Ok(Scale([v as f64; 3]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Scale, E> {
                Ok(Scale([v as f64; 3]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Scale, A::Error> {
                let mut s = [0.0; 3];
                for (i, c) in s.iter_mut().enumerate() {
                    *c = seq
                        .next_element()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                if seq.next_element::<f64>()?.is_some() {
                    return Err(de::Error::invalid_length(4, &self));
                }
                Ok(Scale(s))
            }
        }
        d.deserialize_any(V)
    }
}

/// An error from validation: (entry, message).
type Invalid = (String, String);

/// Where instances go and what they share, validated.
struct Placement {
    rotation: DQuat,
    scale: DVec3,
    color: [f32; 3],
}

fn vec3(v: [f64; 3], what: &str) -> Result<DVec3, String> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(DVec3::from(v))
    } else {
        Err(format!("{what} {v:?} has a non-finite number"))
    }
}

fn number(v: f64, what: &str) -> Result<f64, String> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{what} = {v} is not finite"))
    }
}

fn placement(
    rotation_deg: Option<[f64; 3]>,
    axis_angle: Option<[f64; 4]>,
    scale: Option<&Scale>,
    color: Option<[f64; 3]>,
) -> Result<Placement, String> {
    let rotation = match (rotation_deg, axis_angle) {
        (Some(_), Some(_)) => return Err("give rotation_deg or axis_angle, not both".into()),
        (Some(r), None) => {
            let r = vec3(r, "rotation_deg")?;
            DQuat::from_rotation_z(r.z.to_radians())
                * DQuat::from_rotation_y(r.y.to_radians())
                * DQuat::from_rotation_x(r.x.to_radians())
        }
        (None, Some(aa)) => {
            let axis = vec3([aa[0], aa[1], aa[2]], "axis_angle axis")?;
            let angle = number(aa[3], "axis_angle angle")?;
            if axis.length_squared() == 0.0 {
                return Err("axis_angle has a zero axis".into());
            }
            DQuat::from_axis_angle(axis.normalize(), angle.to_radians())
        }
        (None, None) => DQuat::IDENTITY,
    };
    let scale = match scale {
        Some(s) => vec3(s.0, "scale")?,
        None => DVec3::ONE,
    };
    if scale.cmpeq(DVec3::ZERO).any() {
        return Err(format!("scale {:?} has a zero component", scale.to_array()));
    }
    let color = match color {
        Some(c) => {
            let v = vec3(c, "color")?;
            if v.min_element() < 0.0 || v.max_element() > f32::MAX as f64 {
                return Err(format!("color {c:?} must be >= 0"));
            }
            v.as_vec3().to_array()
        }
        None => [1.0; 3],
    };
    Ok(Placement {
        rotation,
        scale,
        color,
    })
}

/// PCG32 (O'Neill), for deterministic procedural placement.
struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    fn new(seed: u64, stream: u64) -> Self {
        let mut r = Pcg32 {
            state: 0,
            inc: (stream << 1) | 1,
        };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }

    fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    /// Uniform in `[0, 1)` with 53 random bits.
    fn unit(&mut self) -> f64 {
        let bits = ((self.next_u32() as u64) << 32 | self.next_u32() as u64) >> 11;
        bits as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[lo, hi]`.
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// Most generated materials a `[[mesh]]` may ask for (`materials = N`).
pub const MAX_PATCH_MATERIALS: u32 = 65_536;

/// Stream ids, so grid and scatter with the same seed differ.
const GRID_STREAM: u64 = 0x0067_7269_6400;
const SCATTER_STREAM: u64 = 0x0073_6361_7474;

fn build(file: SceneFile, base: &Path) -> Result<Scene, Invalid> {
    let mut meshes: Vec<SceneMesh> = Vec::with_capacity(file.mesh.len());
    for (i, m) in file.mesh.iter().enumerate() {
        let entry = format!("mesh #{} \"{}\"", i + 1, m.name);
        if m.name.is_empty() {
            return Err((entry, "empty name".into()));
        }
        if meshes.iter().any(|o| o.name == m.name) {
            return Err((entry, "duplicate mesh name".into()));
        }
        if m.path.as_os_str().is_empty() {
            return Err((entry, "empty path".into()));
        }
        let generated = m
            .path
            .to_str()
            .is_some_and(|p| p.starts_with(GENERATED_PREFIX));
        if let Some(n) = m.materials {
            if !(1..=MAX_PATCH_MATERIALS).contains(&n) {
                return Err((
                    entry,
                    format!("materials = {n}: must be 1 to {MAX_PATCH_MATERIALS}"),
                ));
            }
            if m.path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("vgeo"))
            {
                return Err((
                    entry,
                    "materials = N needs the source mesh (a .vgeo file keeps its built materials)"
                        .into(),
                ));
            }
        }
        meshes.push(SceneMesh {
            name: m.name.clone(),
            path: if generated {
                m.path.clone()
            } else {
                base.join(&m.path)
            },
            materials: m.materials,
        });
    }
    let find = |name: &str| -> Result<u32, String> {
        meshes
            .iter()
            .position(|m| m.name == name)
            .map(|i| i as u32)
            .ok_or_else(|| {
                let known: Vec<&str> = meshes.iter().map(|m| m.name.as_str()).collect();
                format!(
                    "unknown mesh \"{name}\" (defined: {})",
                    if known.is_empty() {
                        "none".into()
                    } else {
                        known.join(", ")
                    }
                )
            })
    };

    // Count first, so that a huge procedural entry fails before allocating.
    let mut total = file.instance.len() as u64;
    for (i, g) in file.grid.iter().enumerate() {
        let entry = format!("grid #{} (mesh \"{}\")", i + 1, g.mesh);
        if g.count.iter().any(|&c| c < 1) {
            return Err((
                entry,
                format!("count {:?}: every count must be >= 1", g.count),
            ));
        }
        let n = g.count.iter().fold(1u128, |a, &c| a * c as u128);
        if n > MAX_INSTANCES as u128 {
            return Err((
                entry,
                format!(
                    "count {:?} makes {n} instances, more than {MAX_INSTANCES}",
                    g.count
                ),
            ));
        }
        total += n as u64;
    }
    for (i, s) in file.scatter.iter().enumerate() {
        let entry = format!("scatter #{} (mesh \"{}\")", i + 1, s.mesh);
        if s.count < 1 {
            return Err((entry, format!("count = {}: must be >= 1", s.count)));
        }
        if s.count as u64 > MAX_INSTANCES {
            return Err((
                entry,
                format!("count = {} is more than {MAX_INSTANCES}", s.count),
            ));
        }
        total += s.count as u64;
    }
    if total > MAX_INSTANCES {
        return Err((
            "scene".into(),
            format!("{total} instances in all, more than {MAX_INSTANCES}"),
        ));
    }
    if total == 0 {
        return Err((
            "scene".into(),
            "no instances ([[instance]], [[grid]] or [[scatter]])".into(),
        ));
    }

    let mut instances = Vec::with_capacity(total as usize);
    for (i, e) in file.instance.iter().enumerate() {
        let entry = format!("instance #{} (mesh \"{}\")", i + 1, e.mesh);
        let mesh = find(&e.mesh).map_err(|m| (entry.clone(), m))?;
        let p = placement(e.rotation_deg, e.axis_angle, e.scale.as_ref(), e.color)
            .map_err(|m| (entry.clone(), m))?;
        let t = vec3(e.translation, "translation").map_err(|m| (entry, m))?;
        instances.push(Instance {
            mesh,
            transform: DMat4::from_scale_rotation_translation(p.scale, p.rotation, t),
            color: p.color,
        });
    }
    for (i, g) in file.grid.iter().enumerate() {
        let entry = format!("grid #{} (mesh \"{}\")", i + 1, g.mesh);
        let err = |m: String| (entry.clone(), m);
        let mesh = find(&g.mesh).map_err(err)?;
        let p = placement(g.rotation_deg, g.axis_angle, g.scale.as_ref(), g.color).map_err(err)?;
        let spacing = vec3(g.spacing, "spacing").map_err(err)?;
        let origin = vec3(g.origin, "origin").map_err(err)?;
        let jitter = vec3(g.jitter.as_ref().map_or([0.0; 3], |j| j.0), "jitter").map_err(err)?;
        if jitter.min_element() < 0.0 {
            return Err(err(format!("jitter {:?} must be >= 0", jitter.to_array())));
        }
        let mut rng = Pcg32::new(g.seed, GRID_STREAM);
        let [nx, ny, nz] = g.count;
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let mut t = origin + spacing * DVec3::new(i as f64, j as f64, k as f64);
                    if jitter.max_element() > 0.0 {
                        t += DVec3::new(
                            rng.range(-jitter.x, jitter.x),
                            rng.range(-jitter.y, jitter.y),
                            rng.range(-jitter.z, jitter.z),
                        );
                    }
                    let mut rotation = p.rotation;
                    if g.random_rotation {
                        rotation = DQuat::from_rotation_y(rng.range(0.0, std::f64::consts::TAU))
                            * rotation;
                    }
                    instances.push(Instance {
                        mesh,
                        transform: DMat4::from_scale_rotation_translation(p.scale, rotation, t),
                        color: p.color,
                    });
                }
            }
        }
    }
    for (i, s) in file.scatter.iter().enumerate() {
        let entry = format!("scatter #{} (mesh \"{}\")", i + 1, s.mesh);
        let err = |m: String| (entry.clone(), m);
        let mesh = find(&s.mesh).map_err(err)?;
        let p = placement(s.rotation_deg, s.axis_angle, None, s.color).map_err(err)?;
        let lo = vec3(s.min, "min").map_err(err)?;
        let hi = vec3(s.max, "max").map_err(err)?;
        if lo.cmpgt(hi).any() {
            return Err(err(format!("min {:?} is above max {:?}", s.min, s.max)));
        }
        let [a, b] = s.scale_range.unwrap_or([1.0, 1.0]);
        let (a, b) = (
            number(a, "scale_range").map_err(err)?,
            number(b, "scale_range").map_err(err)?,
        );
        if a <= 0.0 || b < a {
            return Err(err(format!("scale_range [{a}, {b}] must have 0 < a <= b")));
        }
        let mut rng = Pcg32::new(s.seed, SCATTER_STREAM);
        for _ in 0..s.count {
            let t = DVec3::new(
                rng.range(lo.x, hi.x),
                rng.range(lo.y, hi.y),
                rng.range(lo.z, hi.z),
            );
            let scale = rng.range(a, b);
            let mut rotation = p.rotation;
            if s.random_yaw {
                rotation = DQuat::from_rotation_y(rng.range(0.0, std::f64::consts::TAU)) * rotation;
            }
            instances.push(Instance {
                mesh,
                transform: DMat4::from_scale_rotation_translation(DVec3::splat(scale), rotation, t),
                color: p.color,
            });
        }
    }

    let camera = match &file.camera {
        None => None,
        Some(c) => Some(camera_desc(c).map_err(|m| ("[camera]".to_string(), m))?),
    };
    let light_dir = match &file.light {
        None => Vec3::from(DEFAULT_LIGHT_DIR).normalize(),
        Some(l) => {
            let d = vec3(l.direction, "direction").map_err(|m| ("[light]".to_string(), m))?;
            if d.length_squared() == 0.0 {
                return Err(("[light]".into(), "direction is zero".into()));
            }
            d.normalize().as_vec3()
        }
    };
    let mut path = Vec::with_capacity(file.path.len());
    for (i, k) in file.path.iter().enumerate() {
        let entry = format!("path #{}", i + 1);
        let eye = vec3(k.eye, "eye").map_err(|m| (entry.clone(), m))?;
        let target = vec3(k.target, "target").map_err(|m| (entry.clone(), m))?;
        if eye == target {
            return Err((entry, "eye and target are the same point".into()));
        }
        path.push(PathKey { eye, target });
    }
    Ok(Scene {
        meshes,
        instances,
        camera,
        light_dir,
        path,
    })
}

fn camera_desc(c: &CameraEntry) -> Result<CameraDesc, String> {
    let eye = vec3(c.eye, "eye")?;
    let target = vec3(c.target, "target")?;
    if eye == target {
        return Err("eye and target are the same point".into());
    }
    let up = vec3(c.up.unwrap_or([0.0, 1.0, 0.0]), "up")?;
    if up.length_squared() == 0.0 {
        return Err("up is zero".into());
    }
    let fov = number(c.fov_y_deg.unwrap_or(45.0), "fov_y_deg")?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(format!("fov_y_deg = {fov} must be in (0, 180)"));
    }
    let near = match c.near {
        None => None,
        Some(n) => {
            let n = number(n, "near")?;
            if !(n > 0.0 && (n as f32) > 0.0) {
                return Err(format!("near = {n} must be > 0"));
            }
            Some(n as f32)
        }
    };
    Ok(CameraDesc {
        eye,
        target,
        up: up.normalize().as_vec3(),
        fov_y_deg: fov as f32,
        near,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Scene, SceneError> {
        Scene::parse(text, Path::new("dir/test.toml"))
    }

    fn err(text: &str) -> String {
        match parse(text) {
            Ok(_) => panic!("expected an error for:\n{text}"),
            Err(e) => e.to_string(),
        }
    }

    const MESH: &str = "[[mesh]]\nname = \"m\"\npath = \"m.ply\"\n";

    #[test]
    fn generated_materials_are_checked() {
        let inst = "[[instance]]\nmesh = \"m\"\n";
        let s = parse(&format!(
            "[[mesh]]\nname = \"m\"\npath = \"m.ply\"\nmaterials = 64\n{inst}"
        ))
        .unwrap();
        assert_eq!(s.meshes[0].materials, Some(64));
        assert!(
            parse(&format!("{MESH}{inst}")).unwrap().meshes[0]
                .materials
                .is_none()
        );
        let e = err("[[mesh]]\nname = \"m\"\npath = \"m.ply\"\nmaterials = 0\n");
        assert!(e.contains("materials = 0") && e.contains("\"m\""), "{e}");
        let e = err("[[mesh]]\nname = \"m\"\npath = \"m.vgeo\"\nmaterials = 4\n");
        assert!(e.contains(".vgeo"), "{e}");
    }

    #[test]
    fn instance_transform_and_paths() {
        let s = parse(&format!(
            "{MESH}[[instance]]\nmesh = \"m\"\ntranslation = [1e9, 2, 3.5]\nrotation_deg = [0, 90, 0]\n\
             scale = [2, 3, 4]\ncolor = [0.5, 0.25, 1]\n[light]\ndirection = [0, 2, 0]\n"
        ))
        .unwrap();
        assert_eq!(s.meshes[0].path, Path::new("dir/m.ply"));
        assert_eq!(s.instances.len(), 1);
        let t = s.instances[0].transform;
        // x axis scaled by 2 then turned 90 deg about Y: +x -> -z.
        let p = t.transform_point3(DVec3::X);
        assert!((p - DVec3::new(1e9, 2.0, 1.5)).length() < 1e-6, "{p}");
        assert_eq!(s.instances[0].color, [0.5, 0.25, 1.0]);
        assert_eq!(s.light_dir, Vec3::Y);
        assert!(s.camera.is_none());
    }

    #[test]
    fn euler_order_is_x_then_y_then_z() {
        let s = parse(&format!(
            "{MESH}[[instance]]\nmesh = \"m\"\nrotation_deg = [90, 90, 0]\n"
        ))
        .unwrap();
        // X first: +y -> +z; then Y: +z -> +x.
        let p = s.instances[0].transform.transform_vector3(DVec3::Y);
        assert!((p - DVec3::X).length() < 1e-12, "{p}");
        let s = parse(&format!(
            "{MESH}[[instance]]\nmesh = \"m\"\naxis_angle = [0, 0, 2, 90]\n"
        ))
        .unwrap();
        let p = s.instances[0].transform.transform_vector3(DVec3::X);
        assert!((p - DVec3::Y).length() < 1e-12, "{p}");
    }

    #[test]
    fn grid_counts_positions_and_determinism() {
        let text = format!(
            "{MESH}[[grid]]\nmesh = \"m\"\ncount = [3, 2, 4]\nspacing = [1, 10, 100]\norigin = [5, 0, 0]\n"
        );
        let s = parse(&text).unwrap();
        assert_eq!(s.instances.len(), 24);
        let mut ts: Vec<[f64; 3]> = s
            .instances
            .iter()
            .map(|i| i.transform.w_axis.truncate().to_array())
            .collect();
        ts.sort_by(|a, b| a.partial_cmp(b).unwrap());
        ts.dedup();
        assert_eq!(ts.len(), 24);
        assert_eq!(ts[0], [5.0, 0.0, 0.0]);
        assert_eq!(ts[23], [7.0, 10.0, 300.0]);

        let jit = format!(
            "{MESH}[[grid]]\nmesh = \"m\"\ncount = [4, 1, 4]\nspacing = [1, 0, 1]\njitter = 0.25\n\
             random_rotation = true\nseed = SEED\n"
        );
        let a = parse(&jit.replace("SEED", "3")).unwrap();
        let b = parse(&jit.replace("SEED", "3")).unwrap();
        let c = parse(&jit.replace("SEED", "4")).unwrap();
        assert_eq!(a, b);
        assert_ne!(a, c);
        for (n, inst) in a.instances.iter().enumerate() {
            let cell = DVec3::new((n % 4) as f64, 0.0, (n / 4) as f64);
            let off = inst.transform.w_axis.truncate() - cell;
            assert!(
                off.abs().max_element() <= 0.25 && off.length() > 0.0,
                "{n}: {off}"
            );
            // Yaw only: the Y axis stays up.
            assert!((inst.transform.transform_vector3(DVec3::Y) - DVec3::Y).length() < 1e-12);
        }
        // Per-axis jitter: none on y, up to 0.5 on z.
        let per_axis = parse(&jit.replace("SEED", "3").replace("0.25", "[0.25, 0, 0.5]")).unwrap();
        let mut max_z: f64 = 0.0;
        for (n, inst) in per_axis.instances.iter().enumerate() {
            let cell = DVec3::new((n % 4) as f64, 0.0, (n / 4) as f64);
            let off = inst.transform.w_axis.truncate() - cell;
            assert!(
                off.x.abs() <= 0.25 && off.y == 0.0 && off.z.abs() <= 0.5,
                "{n}: {off}"
            );
            max_z = max_z.max(off.z.abs());
        }
        assert!(max_z > 0.25, "z jitter never above 0.25: {max_z}");
    }

    #[test]
    fn scatter_counts_ranges_and_determinism() {
        let text = format!(
            "{MESH}[[scatter]]\nmesh = \"m\"\ncount = 200\nseed = SEED\nmin = [-1, 0, 10]\nmax = [1, 0, 20]\n\
             scale_range = [2, 3]\n"
        );
        let a = parse(&text.replace("SEED", "9")).unwrap();
        let b = parse(&text.replace("SEED", "9")).unwrap();
        let c = parse(&text.replace("SEED", "10")).unwrap();
        assert_eq!(a.instances.len(), 200);
        assert_eq!(a, b);
        assert_ne!(a, c);
        let mut yaws = Vec::new();
        for inst in &a.instances {
            let t = inst.transform.w_axis.truncate();
            assert!(
                t.x >= -1.0 && t.x <= 1.0 && t.y == 0.0 && t.z >= 10.0 && t.z <= 20.0,
                "{t}"
            );
            let s = inst.transform.transform_vector3(DVec3::Y).length();
            assert!((2.0..=3.0).contains(&s), "{s}");
            let x = inst.transform.transform_vector3(DVec3::X);
            yaws.push(x.z.atan2(x.x));
        }
        // Positions and yaws spread over their ranges.
        let xs: Vec<f64> = a.instances.iter().map(|i| i.transform.w_axis.x).collect();
        assert!(xs.iter().any(|&x| x < -0.8) && xs.iter().any(|&x| x > 0.8));
        assert!(yaws.iter().any(|&y| y < -2.5) && yaws.iter().any(|&y| y > 2.5));
    }

    #[test]
    fn camera_explicit_and_auto() {
        let s = parse(&format!(
            "{MESH}[[instance]]\nmesh = \"m\"\ntranslation = [1e7, 0, 0]\n[camera]\neye = [1e7, 0, 10]\n\
             target = [1e7, 0, 0]\nfov_y_deg = 60\n"
        ))
        .unwrap();
        let bounds = [([-1.0f32, -1.0, -1.0], [1.0f32, 1.0, 1.0])];
        let cam = s.camera(&bounds, 1.5);
        assert_eq!(cam.position, DVec3::new(1e7, 0.0, 10.0));
        assert!((cam.forward - Vec3::NEG_Z).length() < 1e-6);
        assert!((cam.fov_y - 60f32.to_radians()).abs() < 1e-6);
        // Eye 9 units from the box: near is half of that.
        assert!((cam.near - 4.5).abs() < 1e-5, "{}", cam.near);

        // No camera: frames the transformed boxes, far from the origin, in f64.
        let s = parse(&format!(
            "{MESH}[[instance]]\nmesh = \"m\"\ntranslation = [1e9, 0, 0]\nscale = 2\n\
             [[instance]]\nmesh = \"m\"\ntranslation = [1e9, 0, 4]\n"
        ))
        .unwrap();
        let (lo, hi) = s.bounds(&bounds).unwrap();
        assert_eq!(lo, DVec3::new(1e9 - 2.0, -2.0, -2.0));
        assert_eq!(hi, DVec3::new(1e9 + 2.0, 2.0, 5.0));
        let cam = s.camera(&bounds, 1.0);
        let to_centre = ((lo + hi) * 0.5 - cam.position).normalize().as_vec3();
        assert!(
            to_centre.dot(cam.forward) > 0.9999,
            "{to_centre} {}",
            cam.forward
        );
    }

    #[test]
    fn herd_scene_parses_and_frames_its_instances() {
        let path = Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/assets/scenes/herd.toml"
        ));
        let s = Scene::load(path).unwrap_or_else(|e| panic!("{e}"));
        let names: Vec<&str> = s.meshes.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["spot", "bunny"]);
        assert!(s.meshes[0].path.ends_with("scenes/../spot.obj"));
        assert!(s.meshes[1].path.ends_with("scenes/../bunny.ply"));
        let per_mesh = |m: u32| s.instances.iter().filter(|i| i.mesh == m).count();
        // Triangles: spot.obj 5,856 and bunny.ply 69,451 each; the scene stays under 500k.
        let tris = per_mesh(0) * 5_856 + per_mesh(1) * 69_451;
        assert!(
            per_mesh(0) >= 4 && per_mesh(1) >= 2 && tris < 500_000,
            "{tris}"
        );
        // Object-space boxes of the two meshes: every instance's centre is in view at 4:3 and 16:9.
        let bounds = [
            ([-0.472f32, -0.737, -0.669], [0.472f32, 0.954, 1.049]),
            ([-0.095f32, 0.033, -0.062], [0.061f32, 0.187, 0.059]),
        ];
        for (w, h) in [(800u32, 600u32), (1920, 1080)] {
            let cam = s.camera(&bounds, w as f32 / h as f32);
            let vp = cam.view_proj(w, h);
            for inst in &s.instances {
                let (lo, hi) = bounds[inst.mesh as usize];
                let c = (Vec3::from(lo) + Vec3::from(hi)).as_dvec3() * 0.5;
                let rel = cam.relative_model(&inst.transform);
                let p =
                    crate::camera::project_to_pixel(&vp, rel.transform_point3(c.as_vec3()), w, h)
                        .expect("instance behind the camera");
                assert!(
                    p[0] > 0.0 && p[0] < w as f32 && p[1] > 0.0 && p[1] < h as f32,
                    "{p:?}"
                );
                assert!(p[2] < 1.0, "instance before the near plane");
            }
        }
    }

    #[test]
    fn camera_path_keys_interpolate_and_validate() {
        let s = parse(&format!(
            "{MESH}[[instance]]\nmesh = \"m\"\n[camera]\neye = [0, 0, 9]\ntarget = [0, 0, 0]\n\
             fov_y_deg = 30\nnear = 0.5\n[[path]]\neye = [0, 0, 10]\ntarget = [0, 0, 0]\n\
             [[path]]\neye = [10, 0, 10]\ntarget = [1, 0, 0]\n[[path]]\neye = [10, 0, 0]\n\
             target = [1, 0, -1]\n"
        ))
        .unwrap();
        assert_eq!(s.path.len(), 3);
        assert_eq!(s.path[1].eye, DVec3::new(10.0, 0.0, 10.0));
        let keys = interpolate_path(&s.path, 5);
        let eyes: Vec<DVec3> = keys.iter().map(|k| k.eye).collect();
        assert_eq!(
            eyes,
            [
                DVec3::new(0.0, 0.0, 10.0),
                DVec3::new(5.0, 0.0, 10.0),
                DVec3::new(10.0, 0.0, 10.0),
                DVec3::new(10.0, 0.0, 5.0),
                DVec3::new(10.0, 0.0, 0.0),
            ]
        );
        assert_eq!(keys[1].target, DVec3::new(0.5, 0.0, 0.0));
        assert_eq!(interpolate_path(&s.path, 1), vec![s.path[0]]);
        assert_eq!(interpolate_path(&s.path, 2)[1], s.path[2]);
        // Cameras take the explicit camera's field of view and near plane.
        let bounds = [([-1.0f32; 3], [1.0f32; 3])];
        let cams = s.path_cameras(&bounds, 1.0, 5);
        assert_eq!(cams.len(), 5);
        assert_eq!(cams[3].position, DVec3::new(10.0, 0.0, 5.0));
        assert!((cams[0].fov_y - 30f32.to_radians()).abs() < 1e-6);
        assert_eq!(cams[0].near, 0.5);
        // No path: the scene camera, repeated.
        let s2 = parse(&format!("{MESH}[[instance]]\nmesh = \"m\"\n")).unwrap();
        assert!(s2.path.is_empty());
        let cams = s2.path_cameras(&bounds, 1.0, 3);
        assert_eq!(cams.len(), 3);
        assert_eq!(cams[0].position, s2.camera(&bounds, 1.0).position);
        // Errors name the keyframe.
        let e = err(&format!(
            "{MESH}[[instance]]\nmesh = \"m\"\n[[path]]\neye = [0, 0, 1]\ntarget = [0, 0, 0]\n\
             [[path]]\neye = [1, 1, 1]\ntarget = [1, 1, 1]\n"
        ));
        assert!(e.contains("path #2") && e.contains("same point"), "{e}");
        let e = err(&format!(
            "{MESH}[[instance]]\nmesh = \"m\"\n[[path]]\neye = [0, 0, 1]\n"
        ));
        assert!(e.contains("target"), "{e}");
    }

    #[test]
    fn generated_mesh_paths_are_kept_as_written() {
        let s = parse(
            "[[mesh]]\nname = \"g\"\npath = \"generated:grass\"\n[[instance]]\nmesh = \"g\"\n",
        )
        .unwrap();
        assert_eq!(s.meshes[0].path, Path::new("generated:grass"));
    }

    #[test]
    fn single_mesh_scene() {
        let s = Scene::single_mesh(Path::new("a/b/bunny.ply"));
        assert_eq!(s.meshes[0].name, "bunny");
        assert_eq!(s.instances.len(), 1);
        assert_eq!(s.instances[0].transform, DMat4::IDENTITY);
    }

    #[test]
    fn errors_name_the_file_and_entry() {
        let cases: &[(String, &[&str])] = &[
            (
                format!("{MESH}[[instance]]\nmesh = \"bunyn\"\n"),
                &["instance #1", "unknown mesh \"bunyn\"", "m"],
            ),
            (
                format!("{MESH}[[instance]]\nmesh = \"m\"\ntranslaton = [0, 0, 0]\n"),
                &["unknown field", "translaton"],
            ),
            (
                format!("{MESH}[[instance]]\nmesh = \"m\"\ntranslation = [nan, 0, 0]\n"),
                &["instance #1", "translation", "non-finite"],
            ),
            (
                format!("{MESH}[[instance]]\nmesh = \"m\"\nscale = inf\n"),
                &["instance #1", "scale", "non-finite"],
            ),
            (
                format!("{MESH}[[instance]]\nmesh = \"m\"\nscale = 0\n"),
                &["instance #1", "zero"],
            ),
            (
                format!(
                    "{MESH}[[instance]]\nmesh = \"m\"\nrotation_deg = [0, 0, 0]\naxis_angle = [0, 1, 0, 5]\n"
                ),
                &["not both"],
            ),
            (
                format!("{MESH}[[grid]]\nmesh = \"m\"\ncount = [2, 0, 2]\nspacing = [1, 1, 1]\n"),
                &["grid #1", ">= 1"],
            ),
            (
                format!("{MESH}[[grid]]\nmesh = \"m\"\ncount = [2, -3, 2]\nspacing = [1, 1, 1]\n"),
                &["grid #1", ">= 1"],
            ),
            (
                format!(
                    "{MESH}[[grid]]\nmesh = \"m\"\ncount = [1000, 1000, 101]\nspacing = [1, 1, 1]\n"
                ),
                &["grid #1", "101000000", "more than"],
            ),
            (
                format!(
                    "{MESH}[[scatter]]\nmesh = \"m\"\ncount = 0\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
                ),
                &["scatter #1", ">= 1"],
            ),
            (
                format!(
                    "{MESH}[[scatter]]\nmesh = \"m\"\ncount = 5\nmin = [0, 2, 0]\nmax = [1, 1, 1]\n"
                ),
                &["scatter #1", "above max"],
            ),
            (
                format!(
                    "{MESH}[[scatter]]\nmesh = \"m\"\ncount = 5\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nbogus = 1\n"
                ),
                &["unknown field", "bogus"],
            ),
            (
                format!(
                    "{MESH}[[grid]]\nmesh = \"m\"\ncount = [1000, 1000, 60]\nspacing = [1, 1, 1]\n[[grid]]\nmesh = \"m\"\ncount = [1000, 1000, 60]\nspacing = [1, 1, 1]\n"
                ),
                &["120000000 instances in all"],
            ),
            (MESH.to_string(), &["no instances"]),
            (
                format!("{MESH}{MESH}[[instance]]\nmesh = \"m\"\n"),
                &["mesh #2", "duplicate"],
            ),
            (
                format!(
                    "{MESH}[[instance]]\nmesh = \"m\"\n[camera]\neye = [0, 0, 0]\ntarget = [0, 0, 0]\n"
                ),
                &["[camera]", "same point"],
            ),
            (
                format!(
                    "{MESH}[[instance]]\nmesh = \"m\"\n[camera]\neye = [0, 0, 1]\ntarget = [0, 0, 0]\nfov_y_deg = 180\n"
                ),
                &["[camera]", "fov_y_deg"],
            ),
            (
                format!(
                    "{MESH}[[instance]]\nmesh = \"m\"\n[camera]\neye = [0, 0, 1]\ntarget = [0, 0, 0]\nnear = -1\n"
                ),
                &["[camera]", "near"],
            ),
            (
                format!("{MESH}[[instance]]\nmesh = \"m\"\n[light]\ndirection = [0, 0, 0]\n"),
                &["[light]", "zero"],
            ),
            (
                format!("{MESH}[[instance]]\nmesh = \"m\"\n[light]\ndirection = [0, -inf, 0]\n"),
                &["[light]", "non-finite"],
            ),
            (
                format!("{MESH}[[instance]]\nmesh = \"m\"\n[camera]\neye = [0, 0, 1]\n"),
                &["missing field", "target"],
            ),
            ("[[mesh]]\nname = \"m\"\npath = \n".to_string(), &["line 3"]),
        ];
        for (text, needles) in cases {
            let e = err(text);
            assert!(e.starts_with("dir/test.toml: "), "{e}");
            for n in *needles {
                assert!(e.contains(n), "error {e:?} does not contain {n:?}");
            }
        }
    }

    #[test]
    fn load_reports_a_missing_file() {
        let e = Scene::load(Path::new("/nonexistent/vgeo/scene.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/nonexistent/vgeo/scene.toml") && e.contains("cannot read"),
            "{e}"
        );
    }
}
