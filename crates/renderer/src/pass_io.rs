//! What a pass reads and writes, declared once. A pass names each resource it touches
//! with its use — and, where its shaders reach it through a descriptor, the binding —
//! in one builder chain; from that one declaration come both the descriptor writes
//! ([`crate::bindings::SetWriter`]) and the barrier uses ([`PassUses`], for
//! [`crate::graph::ImageStates::transition`]). A resource is never stated twice, so a
//! binding cannot name an image whose barrier was forgotten, nor a barrier an image the
//! pass does not bind.

use combustion_vk::{vk, Buffer, Device, Image};

use crate::bindings::{SetDecl, SetWriter};
use crate::graph::{BufferUse, ImageUse, PassUses, TrackedImage};
use crate::slot::FrameSlot;

/// One pass's declaration of its inputs and outputs, built per frame.
pub(crate) struct PassIo {
    uses: PassUses,
    /// The descriptor sets the pass binds, each with its writes; bindings go to the last.
    writers: Vec<SetWriter>,
}

impl PassIo {
    /// A pass named `name` (its timings' and messages' name) touching nothing yet.
    pub fn new(name: &'static str) -> Self {
        Self {
            uses: PassUses::images(name, Vec::new()),
            writers: Vec::new(),
        }
    }

    /// The bindings that follow go to `set`, a set of layout `decl` that no pending
    /// frame uses (a frame slot's own). Every binding of `decl` must be given.
    pub fn set(mut self, decl: &'static SetDecl, set: vk::DescriptorSet) -> Self {
        self.writers.push(decl.writer(set));
        self
    }

    /// As [`PassIo::set`], with the frame slot's own set of `decl`.
    pub fn slot_set(self, slot: &FrameSlot, decl: &'static SetDecl) -> Self {
        self.set(decl, slot.set(decl))
    }

    fn writer(&mut self) -> &mut SetWriter {
        self.writers
            .last_mut()
            .expect("PassIo::set names the descriptor set before its bindings")
    }

    /// An acceleration structure the pass's shaders trace through `binding` (built by the
    /// pass itself, which records the barrier after its build).
    pub fn acceleration_structure(
        mut self,
        binding: &str,
        structure: vk::AccelerationStructureKHR,
    ) -> Self {
        self.writer().add_acceleration_structure(binding, structure);
        self
    }

    /// An image the pass's shaders read through `binding` (no sampler: texelFetch),
    /// in the layout of `use_`, which the barriers bring it into.
    pub fn image(mut self, binding: &str, image: &Image, use_: ImageUse) -> Self {
        self.writer().add_image(
            binding,
            image.view(),
            use_.state().layout,
            vk::Sampler::null(),
        );
        self.touches(image.into(), use_)
    }

    /// An image the pass's shaders sample through `binding` with `sampler` (a combined
    /// image sampler, every level and layer), in the layout of `use_`, which the barriers
    /// bring it into.
    pub fn sampled(
        mut self,
        binding: &str,
        image: &Image,
        sampler: vk::Sampler,
        use_: ImageUse,
    ) -> Self {
        self.writer()
            .add_image(binding, image.view(), use_.state().layout, sampler);
        self.touches(image.into(), use_)
    }

    /// As [`PassIo::sampled`], through `view`, a view of `image` other than its own (a
    /// 2D-array view of an image of one layer, say).
    pub fn sampled_view(
        mut self,
        binding: &str,
        image: &Image,
        view: vk::ImageView,
        sampler: vk::Sampler,
        use_: ImageUse,
    ) -> Self {
        self.writer()
            .add_image(binding, view, use_.state().layout, sampler);
        self.touches(image.into(), use_)
    }

    /// Part of `image` (one mip level, say) that the pass's shaders reach through
    /// `binding` by `view`, a view of it (no sampler: a storage image or texelFetch), in
    /// the layout of `use_`. The barriers bring the whole image into that layout.
    pub fn image_view(
        mut self,
        binding: &str,
        image: &Image,
        view: vk::ImageView,
        use_: ImageUse,
    ) -> Self {
        self.writer()
            .add_image(binding, view, use_.state().layout, vk::Sampler::null());
        self.touches(image.into(), use_)
    }

    /// A buffer the pass's shaders reach through `binding`, used as `use_`.
    pub fn buffer(mut self, binding: &str, buffer: &Buffer, use_: BufferUse) -> Self {
        self = self.bind_buffer(binding, buffer);
        self.uses.buffers.push((buffer.raw(), use_));
        self
    }

    /// A buffer the pass uses as `use_` without a descriptor (a vertex stream).
    pub fn uses_buffer(mut self, buffer: &Buffer, use_: BufferUse) -> Self {
        self.uses.buffers.push((buffer.raw(), use_));
        self
    }

    /// The posed vertices of `scene`'s deformed objects, read as vertex streams by a
    /// pass that draws the scene (nothing for a scene without them).
    pub fn posed_vertices(self, scene: &crate::scene_upload::GpuScene) -> Self {
        match &scene.gpu.deform {
            Some(deform) => self.uses_buffer(&deform.posed, BufferUse::VertexInput),
            None => self,
        }
    }

    /// An image bound to `binding` that no barrier of the frame concerns: made ready
    /// once, at upload (an environment's cubes, a placeholder), and only ever read; or
    /// one the pass's shaders never reach (bound because every binding of a set is
    /// written), in the layout it is in.
    pub fn bind_image(
        mut self,
        binding: &str,
        view: vk::ImageView,
        layout: vk::ImageLayout,
        sampler: vk::Sampler,
    ) -> Self {
        self.writer().add_image(binding, view, layout, sampler);
        self
    }

    /// [`PassIo::buffer`] when `used` (the frame's shaders read it), else
    /// [`PassIo::bind_buffer`] (bound only, as every binding of a set must be).
    pub fn buffer_if(self, used: bool, binding: &str, buffer: &Buffer, use_: BufferUse) -> Self {
        if used {
            self.buffer(binding, buffer, use_)
        } else {
            self.bind_buffer(binding, buffer)
        }
    }

    /// A buffer bound to `binding` that no barrier of the frame concerns (written by
    /// the CPU before the submission, or a placeholder the shaders of this frame do not
    /// read).
    pub fn bind_buffer(mut self, binding: &str, buffer: &Buffer) -> Self {
        self.writer().add_buffer(binding, buffer);
        self
    }

    /// An image the pass touches without a descriptor: an attachment it renders into,
    /// or the source or destination of a copy.
    ///
    /// An image declared again with the same use and range is one use (a pass binding
    /// two views of one image, as a mip level built from the level before it); one image
    /// in two uses is a mistake (it has one layout at a time), refused in debug builds.
    pub fn touches(mut self, image: TrackedImage, use_: ImageUse) -> Self {
        let mut same = self
            .uses
            .images
            .iter()
            .filter(|(declared, _)| declared.raw == image.raw);
        match same.next() {
            None => self.uses.images.push((image, use_)),
            Some(&(declared, declared_use)) => debug_assert!(
                declared_use == use_ && same_range(declared.range, image.range),
                "{}: an image declared as {declared_use:?} and as {use_:?}",
                self.uses.name
            ),
        }
        self
    }

    /// Writes the pass's descriptor sets and returns the uses its barriers follow. The
    /// sets must not be in use by a pending frame, nor bound earlier in the command
    /// buffer being recorded.
    pub fn apply(self, device: &Device) -> PassUses {
        for writer in self.writers {
            writer.apply(device);
        }
        self.uses
    }
}

fn same_range(a: vk::ImageSubresourceRange, b: vk::ImageSubresourceRange) -> bool {
    (
        a.aspect_mask,
        a.base_mip_level,
        a.level_count,
        a.base_array_layer,
        a.layer_count,
    ) == (
        b.aspect_mask,
        b.base_mip_level,
        b.level_count,
        b.base_array_layer,
        b.layer_count,
    )
}
