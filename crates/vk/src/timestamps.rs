use std::sync::Arc;

use ash::vk;

use crate::device::Device;
use crate::error::{VkError, VkResultExt};

/// A timestamp query pool: write a timestamp at the start and at the end of each pass,
/// read back the durations in milliseconds once the submission has completed.
///
/// Per frame: [`TimestampQueries::record_reset`] (outside any rendering scope), then
/// [`TimestampQueries::record`] for each index in use, then after the submission has
/// completed [`TimestampQueries::read_ms_if_available`].
pub struct TimestampQueries {
    device: Arc<Device>,
    pool: vk::QueryPool,
    count: u32,
    period_ns: f64,
}

impl TimestampQueries {
    /// A pool of `count` timestamps (indices `0..count`).
    ///
    /// # Errors
    /// [`VkError::InvalidArgument`] when `count` is 0; [`VkError::Unsupported`] when the
    /// device has no timestamps on its graphics and compute queues (pass timings are then
    /// unavailable, which a renderer can live with); [`VkError`] when the pool cannot be
    /// created.
    pub fn new(device: &Arc<Device>, count: u32) -> Result<Self, VkError> {
        if count == 0 {
            return Err(VkError::InvalidArgument {
                what: "TimestampQueries::new",
                why: "a timestamp pool needs at least one timestamp, not 0".into(),
            });
        }
        let limits = device.limits();
        if limits.timestamp_compute_and_graphics == vk::FALSE || limits.timestamp_period <= 0.0 {
            return Err(VkError::Unsupported(
                "the device has no timestamp queries on its graphics and compute queues (timestampComputeAndGraphics)".into(),
            ));
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(count);
        // SAFETY: valid create info.
        let pool =
            unsafe { device.raw().create_query_pool(&info, None) }.what("vkCreateQueryPool")?;
        Ok(Self {
            device: device.clone(),
            pool,
            count,
            period_ns: f64::from(limits.timestamp_period),
        })
    }

    /// The number of timestamps in the pool.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Records the reset of all queries (outside any rendering scope). `cmd` must be in
    /// the recording state.
    pub fn record_reset(&self, cmd: vk::CommandBuffer) {
        unsafe {
            self.device
                .raw()
                .cmd_reset_query_pool(cmd, self.pool, 0, self.count)
        };
    }

    /// Records timestamp `index`, taken once all earlier work reached `stage`. `cmd` must
    /// be in the recording state, `index` below [`TimestampQueries::count`], and the
    /// query reset ([`TimestampQueries::record_reset`]) earlier in the same or an earlier
    /// submission.
    pub fn record(&self, cmd: vk::CommandBuffer, stage: vk::PipelineStageFlags2, index: u32) {
        unsafe {
            self.device
                .raw()
                .cmd_write_timestamp2(cmd, stage, self.pool, index)
        };
    }

    /// Records a copy of the first `count` timestamps (64-bit ticks, clamped to the
    /// pool's count) into `buffer` at `offset`, each 8 bytes after the last, waiting on the
    /// GPU for each to be written (`WAIT`): a frame's own copy of its timings, which the
    /// CPU reads from host-visible memory once the frame has completed without asking the
    /// driver (on some a query read waits for the device). `buffer` needs
    /// `TRANSFER_DST` usage, and `offset` a multiple of 8.
    pub fn record_copy(&self, cmd: vk::CommandBuffer, buffer: vk::Buffer, offset: u64, count: u32) {
        unsafe {
            self.device.raw().cmd_copy_query_pool_results(
                cmd,
                self.pool,
                0,
                count.min(self.count),
                buffer,
                offset,
                8,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        };
    }

    /// Milliseconds since the first of `ticks` (timestamps as [`Self::record_copy`]
    /// wrote them), one per tick.
    pub fn ms_since_first(&self, ticks: &[u64]) -> Vec<f64> {
        let first = ticks.first().copied().unwrap_or(0);
        ticks
            .iter()
            .map(|&t| t.wrapping_sub(first) as f64 * self.period_ns * 1e-6)
            .collect()
    }

    /// Reads all timestamps if the GPU has written them (never waits): `None` while any
    /// is pending. Milliseconds since the first timestamp (index 0), one per index; the
    /// duration of a pass is the difference of its end and start.
    ///
    /// # Errors
    /// [`VkError`] when reading the results fails (e.g. [`VkError::DeviceLost`]).
    pub fn read_ms_if_available(&self) -> Result<Option<Vec<f64>>, VkError> {
        self.read_first_ms_if_available(self.count)
    }

    /// As [`TimestampQueries::read_ms_if_available`], for the first `count` timestamps
    /// alone (those a frame wrote; the rest stay unavailable after a reset). `count` is
    /// clamped to the pool's.
    ///
    /// # Errors
    /// [`VkError`] when reading the results fails (e.g. [`VkError::DeviceLost`]).
    pub fn read_first_ms_if_available(&self, count: u32) -> Result<Option<Vec<f64>>, VkError> {
        let mut ticks = vec![0u64; count.min(self.count) as usize];
        let result = unsafe {
            self.device.raw().get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64,
            )
        };
        match result {
            Ok(()) => {}
            Err(vk::Result::NOT_READY) => return Ok(None),
            Err(e) => return Err(VkError::from_result("vkGetQueryPoolResults", e)),
        }
        let first = ticks.first().copied().unwrap_or(0);
        Ok(Some(
            ticks
                .iter()
                .map(|&t| t.wrapping_sub(first) as f64 * self.period_ns * 1e-6)
                .collect(),
        ))
    }
}

impl Drop for TimestampQueries {
    fn drop(&mut self) {
        unsafe { self.device.raw().destroy_query_pool(self.pool, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support;

    #[test]
    fn a_pool_of_no_timestamps_is_refused() {
        let device = test_support::device();
        let log = device.validation_log();
        match TimestampQueries::new(&device, 0) {
            Err(VkError::InvalidArgument { what, why }) => {
                assert_eq!(what, "TimestampQueries::new");
                assert!(why.contains("at least one"), "{why}");
            }
            Err(e) => panic!("a pool of 0 timestamps was refused with the wrong error: {e}"),
            Ok(_) => panic!("a pool of 0 timestamps was made"),
        }
        let pool = TimestampQueries::new(&device, 2).unwrap();
        drop(pool);
        test_support::finish(device, log);
    }
}
