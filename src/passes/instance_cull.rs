//! Pass `instance_cull`: a thread per instance tests the mesh's bounding sphere against the frustum
//! and pushes the mesh's BVH root for each visible instance into `cluster_cull`'s work queue.
//! In views of [`WALK_WIDE_INSTANCES`] to [`SHARED_RUNS_MAX_INSTANCES`] instances its `shared`
//! variant runs instead: the workgroup shares the cluster tests of its threads' small-instance
//! cuts and local walks (`common/cull.glsl`, shared runs).

use crate::gpu::{Buffer, Cmd, Context, GpuResult, Timer};
use crate::passes::FrameBuffers;
use crate::passes::cull::{self, CullPipelines, Phase};
use crate::scene_gpu::GpuScene;
use crate::shared::{
    CullCounters, INSTANCE_CULL_WORKGROUP_SIZE, SHARED_RUNS_MAX_INSTANCES, WALK_WIDE_INSTANCES,
    compute_grid,
};

/// The `instance_cull` pipelines: the plain one and the `shared` variant, each with and without
/// the partial-residency code ([`CullPipelines`]).
pub struct InstanceCull {
    pipeline: CullPipelines,
    shared: CullPipelines,
    /// The variant forced by tests (`VgeoRenderer::set_shared_runs`); `None`: by the view.
    pub force_shared: Option<bool>,
    /// At most this many workgroups, one per [`INSTANCE_CULL_WORKGROUP_SIZE`] instances in both
    /// phases (tests: each then takes several rounds of items); `None`: the main phase a thread
    /// per instance, the post phase a thread per deferred item.
    pub max_workgroups: Option<u32>,
}

/// Whether a view of `instances` instances takes the `shared` variant: one of at least
/// [`WALK_WIDE_INSTANCES`] (where small instances take their cut from a table and walks reach
/// [`crate::shared::WALK_CLUSTERS_WIDE`] clusters) and fewer than [`SHARED_RUNS_MAX_INSTANCES`].
pub fn shares_runs(instances: u32) -> bool {
    (WALK_WIDE_INSTANCES..SHARED_RUNS_MAX_INSTANCES).contains(&instances)
}

impl InstanceCull {
    /// Creates the pipelines.
    pub fn new(ctx: &Context) -> GpuResult<Self> {
        let pipeline =
            CullPipelines::new(ctx, "instance_cull", crate::shaders::INSTANCE_CULL_COMP)?;
        let shared = CullPipelines::new(
            ctx,
            "instance_cull",
            crate::shaders::INSTANCE_CULL_COMP_SHARED,
        )?;
        Ok(Self {
            pipeline,
            shared,
            force_shared: None,
            max_workgroups: None,
        })
    }

    /// Records the pass: in the main phase one thread per instance, in the post phase one per
    /// deferred item ([`CullCounters::post_dispatch`]), in a 2D grid of workgroups; `streaming`:
    /// some mesh may be partial ([`CullPipelines::pick`]).
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        hzb: &Buffer,
        phase: Phase,
        streaming: bool,
    ) {
        timer.begin(cmd, phase.name("instance_cull", "instance_cull (post)"));
        let pipelines = if self
            .force_shared
            .unwrap_or_else(|| shares_runs(scene.instance_count))
        {
            &self.shared
        } else {
            &self.pipeline
        };
        let pipeline = pipelines.pick(streaming);
        cull::bind(cmd, pipeline, scene, fb, hzb, phase);
        match (phase, self.max_workgroups) {
            // The post phase: a thread per item the main phase deferred (its cull wrote the
            // arguments, behind the barrier that made the rasterizers' visible).
            (Phase::Post, None) => cmd.dispatch_indirect(
                &fb.counters,
                std::mem::offset_of!(CullCounters, post_dispatch) as u64,
            ),
            (_, cap) => {
                let groups = scene
                    .instance_count
                    .div_ceil(INSTANCE_CULL_WORKGROUP_SIZE)
                    .min(cap.unwrap_or(u32::MAX));
                if groups > 0 {
                    let [x, y, z] = compute_grid(groups);
                    cmd.dispatch(x, y, z);
                }
            }
        }
        timer.end(cmd);
    }
}
