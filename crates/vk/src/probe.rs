//! What a [`Device`](crate::Device) was asked to do, counted, and faults injected on
//! request: the means to test the promises a renderer makes about the hot path (no idle
//! wait, one fence wait per reused frame slot, no allocation per frame) and about
//! failure (a failed submission or allocation is a typed error, and nothing hangs or
//! leaks after it). Counting costs one relaxed atomic add per call; a fault is armed
//! only when asked for.

use std::sync::atomic::{AtomicU64, AtomicU8, Ordering};

/// Counts since the device was made ([`crate::Device::counters`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DeviceCounters {
    /// Queue submissions attempted (`vkQueueSubmit2`), failed ones included.
    pub submissions: u64,
    /// Fences waited for (each fence of each `vkWaitForFences` call through the device).
    pub fence_waits: u64,
    /// `vkDeviceWaitIdle` calls.
    pub idle_waits: u64,
    /// `vkQueueWaitIdle` calls (a renderer dropped after recording a host's frames
    /// drains the host's queue).
    pub queue_waits: u64,
    /// Memory allocations requested from the device's allocator, failed ones included.
    pub allocations: u64,
}

impl DeviceCounters {
    /// What happened between `earlier` and `self`.
    pub fn since(&self, earlier: &DeviceCounters) -> DeviceCounters {
        DeviceCounters {
            submissions: self.submissions - earlier.submissions,
            fence_waits: self.fence_waits - earlier.fence_waits,
            idle_waits: self.idle_waits - earlier.idle_waits,
            queue_waits: self.queue_waits - earlier.queue_waits,
            allocations: self.allocations - earlier.allocations,
        }
    }
}

/// A failure to inject into a submission.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InjectedFault {
    /// `VK_ERROR_DEVICE_LOST`.
    DeviceLost,
    /// `VK_ERROR_OUT_OF_DEVICE_MEMORY`.
    OutOfMemory,
}

impl InjectedFault {
    fn code(self) -> u8 {
        match self {
            InjectedFault::DeviceLost => 1,
            InjectedFault::OutOfMemory => 2,
        }
    }

    fn from_code(code: u8) -> Option<InjectedFault> {
        match code {
            1 => Some(InjectedFault::DeviceLost),
            2 => Some(InjectedFault::OutOfMemory),
            _ => None,
        }
    }
}

/// The counters and the armed faults of one device.
#[derive(Debug, Default)]
pub(crate) struct DeviceProbe {
    submissions: AtomicU64,
    fence_waits: AtomicU64,
    idle_waits: AtomicU64,
    queue_waits: AtomicU64,
    allocations: AtomicU64,
    /// The submission (its ordinal in `submissions`, 1-based) that fails; 0: none.
    failing_submission: AtomicU64,
    failing_submission_fault: AtomicU8,
    /// The allocation (its ordinal in `allocations`, 1-based) that fails; 0: none.
    failing_allocation: AtomicU64,
}

impl DeviceProbe {
    pub(crate) fn counters(&self) -> DeviceCounters {
        DeviceCounters {
            submissions: self.submissions.load(Ordering::Relaxed),
            fence_waits: self.fence_waits.load(Ordering::Relaxed),
            idle_waits: self.idle_waits.load(Ordering::Relaxed),
            queue_waits: self.queue_waits.load(Ordering::Relaxed),
            allocations: self.allocations.load(Ordering::Relaxed),
        }
    }

    /// Counts a submission; the fault to return instead of submitting, if it is armed
    /// for this one (it fires once).
    pub(crate) fn submission(&self) -> Option<InjectedFault> {
        let ordinal = self.submissions.fetch_add(1, Ordering::Relaxed) + 1;
        let armed = self.failing_submission.load(Ordering::Relaxed);
        if armed != 0
            && armed == ordinal
            && self
                .failing_submission
                .compare_exchange(armed, 0, Ordering::Relaxed, Ordering::Relaxed)
                .is_ok()
        {
            return InjectedFault::from_code(self.failing_submission_fault.load(Ordering::Relaxed));
        }
        None
    }

    /// Counts an allocation; whether it is the one armed to fail (it fires once).
    pub(crate) fn allocation_fails(&self) -> bool {
        let ordinal = self.allocations.fetch_add(1, Ordering::Relaxed) + 1;
        let armed = self.failing_allocation.load(Ordering::Relaxed);
        armed != 0
            && armed == ordinal
            && self
                .failing_allocation
                .compare_exchange(armed, 0, Ordering::Relaxed, Ordering::Relaxed)
                .is_ok()
    }

    pub(crate) fn fences_waited(&self, count: usize) {
        self.fence_waits.fetch_add(count as u64, Ordering::Relaxed);
    }

    pub(crate) fn idle_wait(&self) {
        self.idle_waits.fetch_add(1, Ordering::Relaxed);
    }

    pub(crate) fn queue_wait(&self) {
        self.queue_waits.fetch_add(1, Ordering::Relaxed);
    }

    pub(crate) fn fail_submission(&self, after: u64, fault: InjectedFault) {
        self.failing_submission_fault
            .store(fault.code(), Ordering::Relaxed);
        let next = self.submissions.load(Ordering::Relaxed) + 1 + after;
        self.failing_submission.store(next, Ordering::Relaxed);
    }

    pub(crate) fn clear_faults(&self) {
        self.failing_submission.store(0, Ordering::Relaxed);
        self.failing_allocation.store(0, Ordering::Relaxed);
    }

    pub(crate) fn fail_allocation(&self, after: u64) {
        let next = self.allocations.load(Ordering::Relaxed) + 1 + after;
        self.failing_allocation.store(next, Ordering::Relaxed);
    }
}
