//! Sampled textures: RGBA8 images uploaded from the CPU, a sampler, and a bindless array of them
//! (one ordinary descriptor set, set 1 of the pipelines that use it, next to the push-descriptor set 0).

use ash::vk;

use super::{Buffer, Context, GpuError, GpuResult, Image, MemoryKind, VkResultExt};

impl Image {
    /// A sampled 8-bit RGBA image (`format`: `R8G8B8A8_UNORM` or `R8G8B8A8_SRGB`) filled with
    /// `rgba` (row-major, top row first), left in `SHADER_READ_ONLY_OPTIMAL` layout.
    pub fn with_rgba8(
        ctx: &Context,
        name: &str,
        width: u32,
        height: u32,
        rgba: &[u8],
        format: vk::Format,
    ) -> GpuResult<Self> {
        Self::with_rgba8_mips(ctx, name, &[(width, height, rgba)], format)
    }

    /// Like [`Image::with_rgba8`] with a mip chain: `levels[i]` = (width, height, texels) of level
    /// i, each level half the previous one (rounded down, at least 1).
    pub fn with_rgba8_mips(
        ctx: &Context,
        name: &str,
        levels: &[(u32, u32, &[u8])],
        format: vk::Format,
    ) -> GpuResult<Self> {
        let Some(&(width, height, _)) = levels.first() else {
            return Err(GpuError::Other(format!("texture `{name}`: no levels")));
        };
        let mut regions = Vec::with_capacity(levels.len());
        let mut offset = 0u64;
        for (i, &(w, h, texels)) in levels.iter().enumerate() {
            let expected = 4 * w as usize * h as usize;
            let (ew, eh) = ((width >> i).max(1), (height >> i).max(1));
            if texels.len() != expected || w != ew || h != eh {
                return Err(GpuError::Other(format!(
                    "texture `{name}` level {i}: {} bytes for {w}x{h} RGBA8 (expected {ew}x{eh})",
                    texels.len()
                )));
            }
            regions.push((offset, w, h));
            offset += expected as u64;
        }
        let image = Image::with_levels(
            ctx,
            name,
            width,
            height,
            format,
            vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            levels.len() as u32,
        )?;
        let mut staging = Buffer::new(
            ctx,
            &format!("{name} (staging)"),
            offset,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryKind::Upload,
        )?;
        for (&(o, _, _), &(_, _, texels)) in regions.iter().zip(levels) {
            staging.write(o, texels)?;
        }
        ctx.submit_and_wait(&format!("upload {name}"), |cmd| {
            cmd.copy_buffer_to_image(&staging, &image, &regions);
            cmd.transition(&image, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL);
        })?;
        Ok(image)
    }
}

/// A bindless array of sampled textures with one shared sampler (linear filtering, repeat
/// addressing): `layout(set = 1, binding = 0) uniform sampler2D textures[]` in GLSL.
pub struct TextureSet {
    ctx: Context,
    pub(crate) layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    pub(crate) set: vk::DescriptorSet,
    sampler: vk::Sampler,
    textures: Vec<Image>,
}

impl TextureSet {
    /// Builds the set over `textures` (at least one; each in `SHADER_READ_ONLY_OPTIMAL`).
    pub fn new(ctx: &Context, name: &str, textures: Vec<Image>) -> GpuResult<Self> {
        if textures.is_empty() {
            return Err(GpuError::Other(format!(
                "texture set `{name}` needs at least one texture"
            )));
        }
        let dev = ctx.device();
        let count = textures.len() as u32;
        let sinfo = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::REPEAT)
            .address_mode_w(vk::SamplerAddressMode::REPEAT)
            .max_lod(vk::LOD_CLAMP_NONE);
        // SAFETY: valid device and create info.
        let sampler = unsafe { dev.create_sampler(&sinfo, None) }.call("vkCreateSampler")?;
        ctx.set_name(sampler, &format!("{name} sampler"));
        let binding = [vk::DescriptorSetLayoutBinding::default()
            .binding(0)
            .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
            .descriptor_count(count)
            .stage_flags(vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE)];
        let linfo = vk::DescriptorSetLayoutCreateInfo::default().bindings(&binding);
        // SAFETY: valid create info.
        let layout = match unsafe { dev.create_descriptor_set_layout(&linfo, None) }
            .call("vkCreateDescriptorSetLayout")
        {
            Ok(l) => l,
            Err(e) => {
                // SAFETY: unused sampler.
                unsafe { dev.destroy_sampler(sampler, None) };
                return Err(e);
            }
        };
        ctx.set_name(layout, &format!("{name} set layout"));
        let sizes = [vk::DescriptorPoolSize {
            ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            descriptor_count: count,
        }];
        let pinfo = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: valid create info.
        let pool = match unsafe { dev.create_descriptor_pool(&pinfo, None) }
            .call("vkCreateDescriptorPool")
        {
            Ok(p) => p,
            Err(e) => {
                // SAFETY: unused objects.
                unsafe {
                    dev.destroy_descriptor_set_layout(layout, None);
                    dev.destroy_sampler(sampler, None);
                }
                return Err(e);
            }
        };
        ctx.set_name(pool, &format!("{name} pool"));
        let mut this = Self {
            ctx: ctx.clone(),
            layout,
            pool,
            set: vk::DescriptorSet::null(),
            sampler,
            textures,
        };
        let layouts = [layout];
        let ainfo = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        // SAFETY: the pool has room for this one set.
        this.set =
            unsafe { dev.allocate_descriptor_sets(&ainfo) }.call("vkAllocateDescriptorSets")?[0];
        ctx.set_name(this.set, name);
        let infos: Vec<vk::DescriptorImageInfo> = this
            .textures
            .iter()
            .map(|t| vk::DescriptorImageInfo {
                sampler,
                image_view: t.view,
                image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            })
            .collect();
        let write = [vk::WriteDescriptorSet::default()
            .dst_set(this.set)
            .dst_binding(0)
            .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
            .image_info(&infos)];
        // SAFETY: the set and the images are valid; nothing uses the set yet.
        unsafe { dev.update_descriptor_sets(&write, &[]) };
        Ok(this)
    }

    /// Number of textures in the array.
    pub fn len(&self) -> usize {
        self.textures.len()
    }

    /// Never true (a set holds at least one texture).
    pub fn is_empty(&self) -> bool {
        self.textures.is_empty()
    }

    /// GPU bytes of the textures (RGBA8, all levels).
    pub fn bytes(&self) -> u64 {
        self.textures
            .iter()
            .map(|t| {
                (0..t.mip_levels)
                    .map(|i| 4 * (t.width >> i).max(1) as u64 * (t.height >> i).max(1) as u64)
                    .sum::<u64>()
            })
            .sum()
    }
}

impl Drop for TextureSet {
    fn drop(&mut self) {
        // SAFETY: GPU work using the set has been waited for (all submissions are waited on).
        unsafe {
            let d = self.ctx.device();
            d.destroy_descriptor_pool(self.pool, None);
            d.destroy_descriptor_set_layout(self.layout, None);
            d.destroy_sampler(self.sampler, None);
        }
    }
}
