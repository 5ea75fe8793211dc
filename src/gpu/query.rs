//! GPU timing of passes with timestamp queries.

use ash::vk;

use super::{Cmd, Context, GpuResult, VkResultExt};

/// Times named passes of one command buffer. Each pass takes two queries.
pub struct Timer {
    ctx: Context,
    pool: Option<vk::QueryPool>,
    /// Pass names (static: recording allocates nothing; capacity reserved at creation).
    names: Vec<&'static str>,
    capacity: u32,
    open: Option<u32>,
    /// Query results of [`Timer::try_total_ms`] (capacity reserved at creation).
    ticks: Vec<u64>,
}

impl Timer {
    /// A timer for up to `max_passes` passes; without timestamp support it records nothing.
    pub fn new(ctx: &Context, max_passes: u32) -> GpuResult<Self> {
        let pool = if ctx.caps().timestamp_period_ns.is_some() {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::TIMESTAMP)
                .query_count(max_passes * 2);
            // SAFETY: valid create info.
            let pool =
                unsafe { ctx.device().create_query_pool(&info, None) }.call("vkCreateQueryPool")?;
            ctx.set_name(pool, "pass timestamps");
            Some(pool)
        } else {
            None
        };
        Ok(Self {
            ctx: ctx.clone(),
            pool,
            names: Vec::with_capacity(max_passes as usize),
            capacity: max_passes,
            open: None,
            ticks: Vec::with_capacity(2 * max_passes as usize),
        })
    }

    /// Resets the timer at the start of a command buffer (must precede any pass).
    pub fn reset(&mut self, cmd: &mut Cmd) {
        self.names.clear();
        self.open = None;
        if let Some(pool) = self.pool {
            cmd.counts().timestamps += 1;
            // SAFETY: the pool is valid; resetting all of its queries outside a render pass.
            unsafe {
                self.ctx
                    .device()
                    .cmd_reset_query_pool(cmd.raw(), pool, 0, self.capacity * 2)
            };
        }
    }

    /// Begins pass `name`: a labelled region and a start timestamp.
    pub fn begin(&mut self, cmd: &mut Cmd, name: &'static str) {
        cmd.begin_label(name);
        let i = self.names.len() as u32;
        if i < self.capacity {
            self.names.push(name);
            self.open = Some(i);
            if let Some(pool) = self.pool {
                cmd.counts().timestamps += 1;
                // SAFETY: query 2i was reset in `reset` and is written once.
                unsafe {
                    cmd.context().inner.sync2.cmd_write_timestamp2(
                        cmd.raw(),
                        vk::PipelineStageFlags2::TOP_OF_PIPE,
                        pool,
                        2 * i,
                    )
                };
            }
        }
    }

    /// Ends the pass begun last.
    pub fn end(&mut self, cmd: &mut Cmd) {
        if let (Some(i), Some(pool)) = (self.open.take(), self.pool) {
            cmd.counts().timestamps += 1;
            // SAFETY: query 2i+1 was reset and is written once.
            unsafe {
                cmd.context().inner.sync2.cmd_write_timestamp2(
                    cmd.raw(),
                    vk::PipelineStageFlags2::BOTTOM_OF_PIPE,
                    pool,
                    2 * i + 1,
                )
            };
        }
        cmd.end_label();
    }

    /// Passes begun since the last reset (the index the next pass's result will have).
    pub fn count(&self) -> usize {
        self.names.len()
    }

    /// Milliseconds per pass of the last submission (after it completed); empty without timestamps.
    pub fn results(&self) -> GpuResult<Vec<(String, f64)>> {
        Ok(self.read(true)?.unwrap_or_default())
    }

    /// Like [`Timer::results`] without waiting: `None` while some timestamp of the last recording
    /// is not yet available (its submission has not completed, or was never submitted).
    pub fn try_results(&self) -> GpuResult<Option<Vec<(String, f64)>>> {
        self.read(false)
    }

    /// The sum of the last recording's pass times in milliseconds, without waiting and without
    /// allocating (for a frame's own bookkeeping): `None` while some timestamp is not yet
    /// available, or without timestamp support or passes.
    pub fn try_total_ms(&mut self) -> GpuResult<Option<f64>> {
        let (Some(pool), Some(period)) = (self.pool, self.ctx.caps().timestamp_period_ns) else {
            return Ok(None);
        };
        let n = self.names.len();
        if n == 0 {
            return Ok(None);
        }
        self.ticks.clear();
        self.ticks.resize(2 * n, 0);
        if !fetch(&self.ctx, pool, &mut self.ticks, false)? {
            return Ok(None);
        }
        Ok(Some((0..n).map(|i| pass_ms(&self.ticks, i, period)).sum()))
    }

    fn read(&self, wait: bool) -> GpuResult<Option<Vec<(String, f64)>>> {
        let (Some(pool), Some(period)) = (self.pool, self.ctx.caps().timestamp_period_ns) else {
            return Ok(Some(Vec::new()));
        };
        let n = self.names.len();
        if n == 0 {
            return Ok(Some(Vec::new()));
        }
        let mut data = vec![0u64; n * 2];
        if !fetch(&self.ctx, pool, &mut data, wait)? {
            return Ok(None);
        }
        Ok(Some(
            self.names
                .iter()
                .enumerate()
                .map(|(i, name)| (name.to_string(), pass_ms(&data, i, period)))
                .collect(),
        ))
    }
}

/// Reads the first `data.len()` queries of `pool` (the last recording's); `false` (no data) while
/// one is not available and `wait` is off.
fn fetch(ctx: &Context, pool: vk::QueryPool, data: &mut [u64], wait: bool) -> GpuResult<bool> {
    let flags = if wait {
        vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT
    } else {
        vk::QueryResultFlags::TYPE_64
    };
    // SAFETY: the queries 0..data.len() were reset and written by the last recording; without
    // WAIT the call returns NOT_READY (no data) until all of them are available.
    let r = unsafe { ctx.device().get_query_pool_results(pool, 0, data, flags) };
    match r {
        Err(vk::Result::NOT_READY) if !wait => Ok(false),
        r => r.call("vkGetQueryPoolResults").map(|()| true),
    }
}

/// Pass `i`'s milliseconds from its two timestamps in `data`.
fn pass_ms(data: &[u64], i: usize, period_ns: f32) -> f64 {
    data[2 * i + 1].wrapping_sub(data[2 * i]) as f64 * period_ns as f64 / 1e6
}

impl Drop for Timer {
    fn drop(&mut self) {
        if let Some(pool) = self.pool {
            // SAFETY: the pool is idle (all submissions are waited on).
            unsafe { self.ctx.device().destroy_query_pool(pool, None) };
        }
    }
}
