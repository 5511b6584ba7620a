//! Push constants declared once, in Rust: [`push_block!`] makes the `#[repr(C)]` struct
//! a pass pushes and the GLSL block its shader includes (`push/NAME.glsl`, generated at
//! start-up like the binding headers), every member at the offset Rust gives it
//! (`layout(offset = …)`), so the two sides cannot disagree and nothing is mirrored by
//! hand. A member whose Rust offset breaks GLSL's alignment rules fails the shader's
//! compilation (every variant's shaders are compiled by the tests).

/// A Rust type a push block may hold, and how GLSL spells it.
pub(crate) trait GlslType {
    /// The GLSL type.
    const GLSL: &'static str;
}

macro_rules! glsl_types {
    ($($ty:ty => $glsl:literal),* $(,)?) => {
        $(impl GlslType for $ty { const GLSL: &'static str = $glsl; })*
    };
}

glsl_types! {
    f32 => "float",
    u32 => "uint",
    i32 => "int",
    [f32; 2] => "vec2",
    [f32; 4] => "vec4",
    [u32; 2] => "uvec2",
    [u32; 4] => "uvec4",
    [i32; 2] => "ivec2",
    [f32; 16] => "mat4",
}

/// A push-constant block made by [`push_block!`].
pub(crate) trait PushBlock: bytemuck::Pod {
    /// The header's name: shaders include `push/NAME.glsl`.
    const HEADER: &'static str;

    /// The header's text: `layout(push_constant) uniform … { … } push;`.
    fn glsl() -> String;

    /// The header's path and text, for the shader sources.
    fn header() -> (String, String) {
        (format!("push/{}.glsl", Self::HEADER), Self::glsl())
    }
}

/// Declares a push-constant struct and its GLSL block:
///
/// ```ignore
/// push_block! {
///     /// What the pass pushes.
///     pub(crate) struct MyPush in "my_pass" {
///         /// Its doc.
///         inverse_view_projection: [f32; 16],
///         extent: [u32; 2],
///     }
/// }
/// ```
///
/// makes `MyPush` (`#[repr(C)]`, `Pod`, its fields public) and `push/my_pass.glsl`,
/// which declares `push.inverse_view_projection` (a `mat4`) and `push.extent` (a
/// `uvec2`).
macro_rules! push_block {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident in $header:literal {
            $($(#[$field_meta:meta])* $field:ident: $ty:ty,)*
        }
    ) => {
        $(#[$meta])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        $vis struct $name {
            $($(#[$field_meta])* pub $field: $ty,)*
        }

        impl $crate::push::PushBlock for $name {
            const HEADER: &'static str = $header;

            fn glsl() -> String {
                let guard = format!("COMBUSTION_PUSH_{}_GLSL", $header.to_uppercase());
                let mut out = format!(
                    "// Generated from combustion_renderer's {} (push_block!); do not edit.\n#ifndef {guard}\n#define {guard}\nlayout(push_constant) uniform {} {{\n",
                    stringify!($name),
                    stringify!($name),
                );
                $(
                    out += &format!(
                        "    layout(offset = {}) {} {};\n",
                        ::core::mem::offset_of!($name, $field),
                        <$ty as $crate::push::GlslType>::GLSL,
                        stringify!($field),
                    );
                )*
                out + "} push;\n#endif\n"
            }
        }
    };
}

pub(crate) use push_block;

#[cfg(test)]
mod tests {
    use super::PushBlock;

    push_block! {
        /// A block of every kind of member.
        struct Example in "example" {
            matrix: [f32; 16],
            position: [f32; 4],
            extent: [u32; 2],
            radius: f32,
            steps: u32,
        }
    }

    #[test]
    fn the_block_declares_each_member_at_its_rust_offset() {
        let glsl = Example::glsl();
        assert!(glsl.contains("layout(push_constant) uniform Example {\n"));
        assert!(glsl.contains("    layout(offset = 0) mat4 matrix;\n"));
        assert!(glsl.contains("    layout(offset = 64) vec4 position;\n"));
        assert!(glsl.contains("    layout(offset = 80) uvec2 extent;\n"));
        assert!(glsl.contains("    layout(offset = 88) float radius;\n"));
        assert!(glsl.contains("    layout(offset = 92) uint steps;\n"));
        assert!(glsl.ends_with("} push;\n#endif\n"));
        assert_eq!(Example::header().0, "push/example.glsl");
        assert_eq!(std::mem::size_of::<Example>(), 96);
    }
}
