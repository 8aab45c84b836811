//! The packed textures (`gpu::textures`) in device buffers: the `tex_table` and `tex_words`
//! read-only storage buffers and their layout entries.

use crate::error::Result;
use crate::integrators::gpu::buffers::storage_buffer;
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::textures::{PackedTextures, TABLE_BINDING_NAME, WORDS_BINDING_NAME};

/// The packed textures on the device.
pub struct TextureBuffers {
    /// `tex_table`: the records.
    pub table: wgpu::Buffer,
    /// `tex_words`: the tables and texels.
    pub words: wgpu::Buffer,
}

impl PackedTextures {
    /// Uploads both buffers (read-only storage; an empty table is one zeroed record).
    pub fn upload(&self, ctx: &GpuContext) -> Result<TextureBuffers> {
        let usage = wgpu::BufferUsages::empty();
        let buffers = TextureBuffers {
            table: storage_buffer(&ctx.device, TABLE_BINDING_NAME, &self.table, usage),
            words: storage_buffer(&ctx.device, WORDS_BINDING_NAME, &self.words, usage),
        };
        ctx.check()?;
        Ok(buffers)
    }
}

impl TextureBuffers {
    /// Bind group entries for the two buffers at bindings `table` and `words`.
    pub fn entries(&self, table: u32, words: u32) -> [wgpu::BindGroupEntry<'_>; 2] {
        [
            wgpu::BindGroupEntry {
                binding: table,
                resource: self.table.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: words,
                resource: self.words.as_entire_binding(),
            },
        ]
    }
}

/// Layout entries (read-only storage, compute stage) for bindings `table` and `words`.
pub fn layout_entries(table: u32, words: u32) -> [wgpu::BindGroupLayoutEntry; 2] {
    let entry = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    [entry(table), entry(words)]
}
