//! Resources given up while frames in flight may still read them. What a renderer
//! replaces goes straight to the retire list of the frame it recorded last (freed when
//! that frame's slot is reused); what is dropped outside it — a [`crate::GpuScene`]
//! going out of scope — waits in the renderer's [`RetireQueue`] until the renderer
//! records its next frame and moves it to that list. So no ordinary Rust code can free
//! memory the GPU still reads.

use std::any::Any;
use std::sync::{Arc, Mutex};

/// A resource kept alive until the frames that may read it have completed.
pub(crate) type Retired = Box<dyn Any + Send>;

/// Resources dropped while the renderer was not looking, shared by the renderer and
/// the scenes it uploaded.
#[derive(Default)]
pub(crate) struct RetireQueue {
    inner: Mutex<QueueState>,
}

#[derive(Default)]
struct QueueState {
    /// The renderer is gone (the host waited for its frames): drop at once.
    closed: bool,
    pending: Vec<Retired>,
}

impl RetireQueue {
    pub fn new() -> Arc<Self> {
        Arc::default()
    }

    /// Keeps `resource` until the renderer takes it, or drops it now if the renderer
    /// is gone.
    pub fn push(&self, resource: Retired) {
        let mut state = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        if state.closed {
            drop(state);
            drop(resource);
        } else {
            state.pending.push(resource);
        }
    }

    /// What was dropped since the last call.
    pub fn take(&self) -> Vec<Retired> {
        let mut state = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        std::mem::take(&mut state.pending)
    }

    /// The renderer is being dropped: returns what is pending, and drops later pushes.
    pub fn close(&self) -> Vec<Retired> {
        let mut state = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        state.closed = true;
        std::mem::take(&mut state.pending)
    }
}
