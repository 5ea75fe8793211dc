//! GPU time per frame: a timestamp written by an empty compute pass in a command buffer submitted
//! before everything else of the frame, another in one after everything else (same submission,
//! `RenderGraphSystems::Begin` .. before `Submit`), resolved and read back in `Finish` (waiting for
//! the GPU: frames do not overlap, so each interval is one frame's GPU work).

use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::Duration;

use bevy::pbr::experimental::meshlet::MeshletPlugin;
use bevy::prelude::*;
use bevy::render::{
    RenderApp, RenderStartup,
    renderer::{PendingCommandBuffers, RenderDevice, RenderGraph, RenderGraphSystems, RenderQueue},
};

use crate::Shared;

#[derive(Default)]
pub struct FrameTimes {
    /// The device has timestamp queries.
    pub supported: bool,
    gpu: BTreeMap<u32, f64>,
}

impl FrameTimes {
    pub fn gpu_ms(&self, frame: u32) -> Option<f64> {
        self.gpu.get(&frame).copied()
    }
    /// Every timed frame has its time (or the device cannot time).
    pub fn complete(&self, frames: u32) -> bool {
        !self.supported || (0..frames).all(|i| self.gpu.contains_key(&i))
    }
}

/// The first Vulkan adapter wgpu picks (high performance), as Bevy will; with `meshlet`, an error
/// naming the features Bevy's meshlets need that it lacks.
pub fn check_adapter(meshlet: bool) -> Result<String, String> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::VULKAN;
    let instance = wgpu::Instance::new(desc);
    let adapter = bevy::tasks::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
    }))
    .map_err(|e| format!("no Vulkan adapter: {e}"))?;
    let info = adapter.get_info();
    let name = format!(
        "{} ({:?}, {} {})",
        info.name, info.device_type, info.driver, info.driver_info
    );
    if meshlet {
        let need = MeshletPlugin::required_wgpu_features();
        let missing = need - adapter.features();
        if !missing.is_empty() {
            let names: Vec<&str> = missing.features_wgpu.iter_names().map(|(n, _)| n).collect();
            return Err(format!(
                "{name} lacks GPU features Bevy's meshlets (virtual geometry) need: {} \
                 (e.g. lavapipe has no 64-bit image atomics); --plain renders ordinary meshes instead",
                names.join(" | ")
            ));
        }
    }
    if !adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
        eprintln!("vgeo-peer-bevy: warning: {name} has no timestamp queries: no GPU times");
    }
    Ok(name)
}

pub struct TimingPlugin(pub Arc<Shared>);

#[derive(Resource, Clone)]
struct SharedRes(Arc<Shared>);

#[derive(Resource)]
struct Timestamps {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
    period_ns: f32,
}

/// The timed frame being drawn (read at the frame's start), or none.
#[derive(Resource, Default)]
struct CurrentTag(Option<u32>);

impl Plugin for TimingPlugin {
    fn build(&self, app: &mut App) {
        let shared = SharedRes(self.0.clone());
        let render_app = app.sub_app_mut(RenderApp);
        render_app
            .insert_resource(shared)
            .init_resource::<CurrentTag>()
            .add_systems(RenderStartup, init_timestamps)
            .add_systems(
                RenderGraph,
                (
                    begin_frame.in_set(RenderGraphSystems::Begin),
                    end_frame
                        .after(RenderGraphSystems::Render)
                        .before(RenderGraphSystems::Submit),
                    read_frame.in_set(RenderGraphSystems::Finish),
                ),
            );
    }
}

fn init_timestamps(
    mut commands: Commands,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    shared: Res<SharedRes>,
) {
    let supported = device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
    shared.0.times.lock().unwrap().supported = supported;
    if !supported {
        return;
    }
    let dev = device.wgpu_device();
    commands.insert_resource(Timestamps {
        set: dev.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("peer frame timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        }),
        resolve: dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("peer timestamp resolve"),
            size: 16,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        }),
        read: dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("peer timestamp read"),
            size: 16,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }),
        period_ns: queue.get_timestamp_period(),
    });
}

fn stamp(device: &RenderDevice, ts: &Timestamps, index: u32) -> wgpu::CommandEncoder {
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("peer timestamp"),
    });
    drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("peer timestamp"),
        timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
            query_set: &ts.set,
            beginning_of_pass_write_index: Some(index),
            end_of_pass_write_index: None,
        }),
    }));
    encoder
}

fn begin_frame(
    device: Res<RenderDevice>,
    ts: Option<Res<Timestamps>>,
    shared: Res<SharedRes>,
    mut tag: ResMut<CurrentTag>,
    mut pending: ResMut<PendingCommandBuffers>,
) {
    let t = shared.0.tag.load(Ordering::SeqCst);
    tag.0 = (t >= 0).then_some(t as u32);
    let (Some(ts), Some(_)) = (ts, tag.0) else {
        return;
    };
    // A finished buffer: submitted before the frame's other buffers and encoders.
    pending.push([stamp(&device, &ts, 0).finish()]);
}

fn end_frame(
    device: Res<RenderDevice>,
    ts: Option<Res<Timestamps>>,
    tag: Res<CurrentTag>,
    mut pending: ResMut<PendingCommandBuffers>,
) {
    let (Some(ts), Some(_)) = (ts, tag.0) else {
        return;
    };
    let mut encoder = stamp(&device, &ts, 1);
    encoder.resolve_query_set(&ts.set, 0..2, &ts.resolve, 0);
    encoder.copy_buffer_to_buffer(&ts.resolve, 0, &ts.read, 0, 16);
    pending.push_encoder(encoder);
}

fn read_frame(
    device: Res<RenderDevice>,
    ts: Option<Res<Timestamps>>,
    tag: Res<CurrentTag>,
    shared: Res<SharedRes>,
) {
    let (Some(ts), Some(frame)) = (ts, tag.0) else {
        return;
    };
    let slice = ts.read.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    if let Err(e) = device.poll(wgpu::PollType::Wait {
        submission_index: None,
        timeout: Some(Duration::from_secs(120)),
    }) {
        eprintln!("vgeo-peer-bevy: error: waiting for frame {frame}'s GPU work: {e}");
        std::process::exit(5);
    }
    match rx.recv_timeout(Duration::from_secs(10)) {
        Ok(Ok(())) => {
            let data = slice.get_mapped_range();
            let b = u64::from_le_bytes(data[0..8].try_into().unwrap());
            let e = u64::from_le_bytes(data[8..16].try_into().unwrap());
            drop(data);
            ts.read.unmap();
            let ms = e.wrapping_sub(b) as f64 * ts.period_ns as f64 / 1e6;
            shared.0.times.lock().unwrap().gpu.insert(frame, ms);
        }
        other => {
            eprintln!("vgeo-peer-bevy: error: frame {frame}'s timestamps not read back: {other:?}");
        }
    }
}
