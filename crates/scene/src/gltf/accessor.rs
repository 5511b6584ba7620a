//! Reading accessors with every range checked (no trust in the JSON). Its arithmetic
//! on sizes and offsets from the file cannot overflow: clippy's `arithmetic_side_effects`
//! is denied here (each element is found by `element`'s checked arithmetic).
#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]

use gltf::json;
use gltf::json::accessor::{ComponentType, Type};
use gltf::json::validation::Checked;

use super::source::Buffers;

/// Accessors without a buffer view are zeros (plus sparse values); they cost memory
/// without any data backing them, so the elements such accessors give, every read of
/// them counted, are capped per file (a per-accessor cap alone would let a file of a few
/// hundred bytes name a thousand of them).
pub(crate) const MAX_UNBACKED_ELEMENTS: u64 = 1 << 22;

fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

fn type_name(t: Type) -> &'static str {
    match t {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

fn dimensions(t: Type) -> usize {
    match t {
        Type::Scalar => 1,
        Type::Vec2 => 2,
        Type::Vec3 => 3,
        Type::Vec4 | Type::Mat2 => 4,
        Type::Mat3 => 9,
        Type::Mat4 => 16,
    }
}

/// The first four bytes of `bytes`, zeros past its end (callers pass one component's
/// own bytes, found by `element`'s checked ranges).
fn first_four(bytes: &[u8]) -> [u8; 4] {
    let mut out = [0; 4];
    for (o, b) in out.iter_mut().zip(bytes) {
        *o = *b;
    }
    out
}

fn read_component(bytes: &[u8], c: ComponentType, normalized: bool) -> f32 {
    let [b0, b1, b2, b3] = first_four(bytes);
    match c {
        ComponentType::F32 => f32::from_le_bytes([b0, b1, b2, b3]),
        ComponentType::U32 => u32::from_le_bytes([b0, b1, b2, b3]) as f32,
        ComponentType::U16 => {
            let v = f32::from(u16::from_le_bytes([b0, b1]));
            if normalized {
                v / 65535.0
            } else {
                v
            }
        }
        ComponentType::I16 => {
            let v = f32::from(i16::from_le_bytes([b0, b1]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        ComponentType::U8 => {
            let v = f32::from(b0);
            if normalized {
                v / 255.0
            } else {
                v
            }
        }
        ComponentType::I8 => {
            let v = f32::from(b0 as i8);
            if normalized {
                (v / 127.0).max(-1.0)
            } else {
                v
            }
        }
    }
}

fn read_index(bytes: &[u8], c: ComponentType) -> u32 {
    let [b0, b1, b2, b3] = first_four(bytes);
    match c {
        ComponentType::U8 | ComponentType::I8 => u32::from(b0),
        ComponentType::U16 | ComponentType::I16 => u32::from(u16::from_le_bytes([b0, b1])),
        ComponentType::U32 | ComponentType::F32 => u32::from_le_bytes([b0, b1, b2, b3]),
    }
}

/// Byte range checks for `count` elements of `element_size` bytes at `offset` with
/// `stride` inside a view of `view_length` bytes.
fn check_range(
    offset: u64,
    count: u64,
    element_size: usize,
    stride: usize,
    view_length: usize,
) -> Result<(), String> {
    if count == 0 {
        return Ok(());
    }
    let last = count
        .checked_sub(1)
        .and_then(|x| x.checked_mul(stride as u64))
        .and_then(|x| x.checked_add(offset))
        .and_then(|x| x.checked_add(element_size as u64));
    match last {
        Some(end) if end <= view_length as u64 => Ok(()),
        _ => Err(format!(
            "{count} elements of {element_size} bytes (stride {stride}) from byte {offset} need more than the buffer view's {view_length} bytes"
        )),
    }
}

/// The `size` bytes of element `i` of a view (at `offset + i·stride`), or `None` past its
/// end (which `check_range` refuses before any element is read).
fn element(view: &[u8], offset: usize, i: usize, stride: usize, size: usize) -> Option<&[u8]> {
    let start = i.checked_mul(stride)?.checked_add(offset)?;
    view.get(start..start.checked_add(size)?)
}

/// `N` components of `csize` bytes each, read from an element's bytes.
fn components<const N: usize>(
    bytes: &[u8],
    csize: usize,
    component: ComponentType,
    normalized: bool,
) -> [f32; N] {
    let mut each = bytes.chunks_exact(csize);
    std::array::from_fn(|_| {
        each.next()
            .map_or(0.0, |b| read_component(b, component, normalized))
    })
}

/// A component type in words, for messages.
fn component_name(component: ComponentType) -> &'static str {
    match component {
        ComponentType::I8 => "signed bytes",
        ComponentType::U8 => "unsigned bytes",
        ComponentType::I16 => "signed shorts",
        ComponentType::U16 => "unsigned shorts",
        ComponentType::U32 => "unsigned ints",
        ComponentType::F32 => "floats",
    }
}

/// Accessor `index` with its validated component type and element type.
fn checked_accessor(
    root: &json::Root,
    index: usize,
) -> Result<(&json::Accessor, json::accessor::ComponentType, &Type), String> {
    let accessor = root
        .accessors
        .get(index)
        .ok_or_else(|| format!("accessor {index} does not exist"))?;
    let (Checked::Valid(component), Checked::Valid(ty)) =
        (&accessor.component_type, &accessor.type_)
    else {
        return Err(format!(
            "accessor {index} has an invalid componentType or type"
        ));
    };
    Ok((accessor, component.0, ty))
}

/// Reads accessor `index` as vertex colours (glTF COLOR_0): VEC3 (alpha 1) or VEC4, of
/// floats or normalised unsigned bytes or shorts, as the specification allows; anything
/// else is an error naming what the accessor is.
pub(crate) fn read_colors(
    root: &json::Root,
    buffers: &mut Buffers,
    index: usize,
) -> Result<Vec<[f32; 4]>, String> {
    use json::accessor::ComponentType as C;
    let (accessor, component, ty) = checked_accessor(root, index)?;
    let allowed = match component {
        C::F32 => true,
        C::U8 | C::U16 => accessor.normalized,
        _ => false,
    };
    if !allowed {
        return Err(format!(
            "accessor {index} is {}{}; colours are floats or normalised unsigned bytes or shorts",
            if accessor.normalized {
                "normalised "
            } else {
                ""
            },
            component_name(component)
        ));
    }
    match dimensions(*ty) {
        4 => read_floats::<4>(root, buffers, index),
        3 => Ok(read_floats::<3>(root, buffers, index)?
            .into_iter()
            .map(|[r, g, b]| [r, g, b, 1.0])
            .collect()),
        _ => Err(format!(
            "accessor {index} is {}, expected VEC3 or VEC4",
            type_name(*ty)
        )),
    }
}

/// Reads accessor `index` as `N` floats per element (integer components converted, and
/// normalised when the accessor says so).
pub(crate) fn read_floats<const N: usize>(
    root: &json::Root,
    buffers: &mut Buffers,
    index: usize,
) -> Result<Vec<[f32; N]>, String> {
    let (accessor, component, ty) = checked_accessor(root, index)?;
    if dimensions(*ty) != N {
        return Err(format!(
            "accessor {index} is {}, expected {} components",
            type_name(*ty),
            N
        ));
    }
    let count = accessor.count.0;
    let csize = component_size(component);
    let element_size = csize.saturating_mul(N);
    let mut out: Vec<[f32; N]> = match accessor.buffer_view {
        None => {
            let total = buffers.unbacked_elements.saturating_add(count);
            if total > MAX_UNBACKED_ELEMENTS {
                return Err(format!(
                    "accessor {index} has no buffer view and {count} elements: the file's accessors without one would hold {total} elements, at most {MAX_UNBACKED_ELEMENTS} per file"
                ));
            }
            buffers.unbacked_elements = total;
            vec![[0.0; N]; count as usize]
        }
        Some(view_index) => {
            let (data, range, stride) = buffers
                .view(view_index.value())
                .map_err(|e| format!("accessor {index}: {e}"))?;
            let stride = stride.unwrap_or(element_size);
            if stride < element_size {
                return Err(format!(
                    "accessor {index}: byteStride {stride} is smaller than an element ({element_size} bytes)"
                ));
            }
            let view = data
                .get(range)
                .ok_or_else(|| format!("accessor {index}: its view is past its buffer's end"))?;
            let offset = accessor.byte_offset.map_or(0, |o| o.0);
            check_range(offset, count, element_size, stride, view.len())
                .map_err(|e| format!("accessor {index}: {e}"))?;
            let offset = offset as usize;
            (0..count as usize)
                .map(|i| {
                    element(view, offset, i, stride, element_size)
                        .map(|b| components(b, csize, component, accessor.normalized))
                        .ok_or_else(|| format!("accessor {index}: element {i} lies past its view"))
                })
                .collect::<Result<_, _>>()?
        }
    };
    if let Some(sparse) = &accessor.sparse {
        let sparse_count = sparse.count.0;
        if sparse_count > count {
            return Err(format!(
                "accessor {index}: sparse count {sparse_count} exceeds the accessor's count {count}"
            ));
        }
        let Checked::Valid(index_type) = &sparse.indices.component_type else {
            return Err(format!(
                "accessor {index}: invalid sparse index componentType"
            ));
        };
        let index_type = index_type.0;
        if !matches!(
            index_type,
            ComponentType::U8 | ComponentType::U16 | ComponentType::U32
        ) {
            return Err(format!(
                "accessor {index}: sparse indices must be unsigned integers"
            ));
        }
        let isize = component_size(index_type);
        let (idata, irange, _) = buffers
            .view(sparse.indices.buffer_view.value())
            .map_err(|e| format!("accessor {index} sparse indices: {e}"))?;
        let iview = idata.get(irange).ok_or_else(|| {
            format!("accessor {index} sparse indices: the view is past its buffer's end")
        })?;
        let ioffset = sparse.indices.byte_offset.0;
        check_range(ioffset, sparse_count, isize, isize, iview.len())
            .map_err(|e| format!("accessor {index} sparse indices: {e}"))?;
        let (vdata, vrange, _) = buffers
            .view(sparse.values.buffer_view.value())
            .map_err(|e| format!("accessor {index} sparse values: {e}"))?;
        let vview = vdata.get(vrange).ok_or_else(|| {
            format!("accessor {index} sparse values: the view is past its buffer's end")
        })?;
        let voffset = sparse.values.byte_offset.0;
        check_range(
            voffset,
            sparse_count,
            element_size,
            element_size,
            vview.len(),
        )
        .map_err(|e| format!("accessor {index} sparse values: {e}"))?;
        let mut previous: Option<usize> = None;
        for k in 0..sparse_count as usize {
            let past = || format!("accessor {index}: sparse entry {k} lies past its view");
            let at = element(iview, ioffset as usize, k, isize, isize).ok_or_else(past)?;
            let target = read_index(at, index_type) as usize;
            // glTF: sparse indices strictly increase (sorted, each element once).
            if let Some(previous) = previous.filter(|&p| target <= p) {
                return Err(format!(
                    "accessor {index}: sparse indices must strictly increase, but index {k} is {target} after {previous}"
                ));
            }
            previous = Some(target);
            let slot = out.get_mut(target).ok_or_else(|| {
                format!(
                    "accessor {index}: sparse index {target} is out of range ({count} elements)"
                )
            })?;
            let values =
                element(vview, voffset as usize, k, element_size, element_size).ok_or_else(past)?;
            *slot = components(values, csize, component, accessor.normalized);
        }
    }
    Ok(out)
}

/// Reads an index accessor (unsigned byte, short or int scalars).
pub(crate) fn read_indices(
    root: &json::Root,
    buffers: &mut Buffers,
    index: usize,
) -> Result<Vec<u32>, String> {
    let (accessor, component, ty) = checked_accessor(root, index)?;
    if *ty != Type::Scalar
        || !matches!(
            component,
            ComponentType::U8 | ComponentType::U16 | ComponentType::U32
        )
    {
        return Err(format!(
            "index accessor {index} must be SCALAR unsigned byte, short or int, not {} {}",
            type_name(*ty),
            component_name(component)
        ));
    }
    if accessor.sparse.is_some() || accessor.buffer_view.is_none() {
        // Rare but legal: go through the general path, then convert (exact below 2²⁴).
        let values = read_floats::<1>(root, buffers, index)?;
        return Ok(values.into_iter().map(|[v]| v as u32).collect());
    }
    let count = accessor.count.0;
    let size = component_size(component);
    let view_index = accessor.buffer_view.map(|v| v.value()).unwrap_or(0);
    let (data, range, stride) = buffers
        .view(view_index)
        .map_err(|e| format!("index accessor {index}: {e}"))?;
    let stride = stride.unwrap_or(size);
    if stride < size {
        return Err(format!(
            "index accessor {index}: byteStride {stride} is smaller than an index ({size} bytes)"
        ));
    }
    let view = data
        .get(range)
        .ok_or_else(|| format!("index accessor {index}: its view is past its buffer's end"))?;
    let offset = accessor.byte_offset.map_or(0, |o| o.0);
    check_range(offset, count, size, stride, view.len())
        .map_err(|e| format!("index accessor {index}: {e}"))?;
    let offset = offset as usize;
    (0..count as usize)
        .map(|i| {
            element(view, offset, i, stride, size)
                .map(|b| read_index(b, component))
                .ok_or_else(|| format!("index accessor {index}: index {i} lies past its view"))
        })
        .collect()
}

/// Reads a `JOINTS_n` accessor: VEC4 of unsigned bytes or shorts, not normalised.
pub(crate) fn read_joints(
    root: &json::Root,
    buffers: &mut Buffers,
    index: usize,
) -> Result<Vec<[u32; 4]>, String> {
    let (accessor, component, _) = checked_accessor(root, index)?;
    if !matches!(component, ComponentType::U8 | ComponentType::U16) || accessor.normalized {
        return Err(format!(
            "accessor {index} is {}{}; joints are unsigned bytes or shorts",
            if accessor.normalized {
                "normalised "
            } else {
                ""
            },
            component_name(component),
        ));
    }
    Ok(read_floats::<4>(root, buffers, index)?
        .into_iter()
        .map(|j| j.map(|x| x as u32))
        .collect())
}

/// Reads a `WEIGHTS_n` accessor or an animation's output: floats, or normalised unsigned
/// bytes or shorts (and, with `signed`, normalised signed ones, as rotations and morph
/// weights may be), `N` per element.
pub(crate) fn read_unit_floats<const N: usize>(
    root: &json::Root,
    buffers: &mut Buffers,
    index: usize,
    signed: bool,
) -> Result<Vec<[f32; N]>, String> {
    let (accessor, component, _) = checked_accessor(root, index)?;
    let allowed = match component {
        ComponentType::F32 => true,
        ComponentType::U8 | ComponentType::U16 => accessor.normalized,
        ComponentType::I8 | ComponentType::I16 => accessor.normalized && signed,
        ComponentType::U32 => false,
    };
    if !allowed {
        return Err(format!(
            "accessor {index} is {}{}; floats or normalised {}integers expected",
            if accessor.normalized {
                "normalised "
            } else {
                ""
            },
            component_name(component),
            if signed { "" } else { "unsigned " },
        ));
    }
    read_floats::<N>(root, buffers, index)
}

/// Reads an accessor of floats only (animation key times, translations, scales, morph
/// displacements, inverse bind matrices), `N` per element.
pub(crate) fn read_f32<const N: usize>(
    root: &json::Root,
    buffers: &mut Buffers,
    index: usize,
) -> Result<Vec<[f32; N]>, String> {
    let (_, component, _) = checked_accessor(root, index)?;
    if component != ComponentType::F32 {
        return Err(format!(
            "accessor {index} is {}; floats expected",
            component_name(component)
        ));
    }
    read_floats::<N>(root, buffers, index)
}
