//! Pass `cluster_cull`: persistent workgroups traverse every visible instance's BVH from a global
//! work queue (frustum and LOD tests per node), apply the cut rule per cluster and append the drawn
//! clusters to the visible list and to the SW or HW rasterizer's list. See the shader's header for
//! the queue protocol and termination.

use crate::gpu::{Buffer, Caps, Cmd, Context, GpuResult, Timer};
use crate::passes::FrameBuffers;
use crate::passes::cull::{self, CullPipelines, Phase};
use crate::scene_gpu::GpuScene;

/// The `cluster_cull` pipelines (with and without the partial-residency code) and its persistent
/// workgroup count.
pub struct ClusterCull {
    pipelines: CullPipelines,
    workgroups: u32,
}

/// How many persistent workgroups to launch: `VGEO_CULL_WORKGROUPS` if set, else what the device
/// can keep resident: a CPU device (lavapipe) runs one workgroup per worker thread, so its thread
/// count; a GPU gets 256 (far below what one H100 keeps resident).
pub fn default_workgroups(caps: &Caps) -> u32 {
    if let Some(n) = std::env::var("VGEO_CULL_WORKGROUPS")
        .ok()
        .and_then(|v| v.parse::<u32>().ok())
    {
        return n.max(1);
    }
    if caps.device_type == "cpu" {
        std::env::var("LP_NUM_THREADS")
            .ok()
            .and_then(|v| v.parse::<u32>().ok())
            .unwrap_or_else(|| {
                std::thread::available_parallelism()
                    .map(|n| n.get() as u32)
                    .unwrap_or(1)
            })
            .max(1)
    } else {
        256
    }
}

impl ClusterCull {
    /// Creates the pipeline with `workgroups` persistent workgroups.
    pub fn new(ctx: &Context, workgroups: u32) -> GpuResult<Self> {
        let pipelines = CullPipelines::new(ctx, "cluster_cull", crate::shaders::CLUSTER_CULL_COMP)?;
        Ok(Self {
            pipelines,
            workgroups: workgroups.max(1),
        })
    }

    /// Persistent workgroups launched.
    pub fn workgroups(&self) -> u32 {
        self.workgroups
    }

    /// Records the pass; `streaming`: some mesh may be partial ([`CullPipelines::pick`]).
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
        timer.begin(cmd, phase.name("cluster_cull", "cluster_cull (post)"));
        cull::bind(cmd, self.pipelines.pick(streaming), scene, fb, hzb, phase);
        cmd.dispatch(self.workgroups, 1, 1);
        timer.end(cmd);
    }
}
