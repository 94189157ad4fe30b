//! Accessors read as the glTF 2.0 specification defines them (Khronos, *glTF 2.0
//! Specification*, 2021, §3.6.2 "Accessors" and §3.7.2.1 "Meshes: attributes"; the
//! quantized types of `KHR_mesh_quantization`): component type, element type, the buffer
//! view's stride, sparse substitutions, and the normalisation of §3.11's table — each checked
//! against the bytes there are and against the use the mesh makes of the accessor.

use gltf::json::accessor::{ComponentType, GenericComponentType, Type};
use gltf::json::validation::Checked;

use super::buffers::Buffers;

/// What a primitive (or an instanced node) uses an accessor for; each use allows the
/// element and component types the specification lists for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Use {
    Position,
    Normal,
    TexCoord,
    Color,
    Indices,
    InstanceTranslation,
    InstanceRotation,
    InstanceScale,
}

impl Use {
    pub(super) fn name(self) -> &'static str {
        match self {
            Use::Position => "POSITION",
            Use::Normal => "NORMAL",
            Use::TexCoord => "TEXCOORD_0",
            Use::Color => "COLOR_0",
            Use::Indices => "the indices",
            Use::InstanceTranslation => "TRANSLATION",
            Use::InstanceRotation => "ROTATION",
            Use::InstanceScale => "SCALE",
        }
    }

    /// The element types this use takes.
    fn types(self) -> &'static [Type] {
        match self {
            Use::Position | Use::Normal | Use::InstanceTranslation | Use::InstanceScale => &[Type::Vec3],
            Use::TexCoord => &[Type::Vec2],
            Use::Color => &[Type::Vec3, Type::Vec4],
            Use::Indices => &[Type::Scalar],
            Use::InstanceRotation => &[Type::Vec4],
        }
    }

    /// Whether this use takes components of type `component`, `normalized` or not: the core
    /// specification's table, widened by `KHR_mesh_quantization` for positions, normals and
    /// texture coordinates (read whether or not the file declares the extension).
    fn takes(self, component: ComponentType, normalized: bool) -> bool {
        use ComponentType::{F32, I8, I16, U8, U16, U32};
        match (self, component) {
            (_, F32) => !normalized && self != Use::Indices,
            (Use::Indices, U8 | U16 | U32) => !normalized,
            (Use::Position, I8 | U8 | I16 | U16) => true,
            (Use::Normal | Use::InstanceRotation, I8 | I16) => normalized,
            (Use::TexCoord, I8 | U8 | I16 | U16) => true,
            (Use::Color, U8 | U16) => normalized,
            _ => false,
        }
    }

    fn allowed(self) -> &'static str {
        match self {
            Use::Position => "VEC3 of floats, or of (normalized) bytes or shorts with KHR_mesh_quantization",
            Use::Normal => "VEC3 of floats, or of normalized bytes or shorts",
            Use::TexCoord => "VEC2 of floats, or of (normalized) bytes or shorts",
            Use::Color => "VEC3 or VEC4 of floats, or of normalized unsigned bytes or shorts",
            Use::Indices => "SCALAR of unsigned bytes, shorts or ints, not normalized",
            Use::InstanceTranslation | Use::InstanceScale => "VEC3 of floats",
            Use::InstanceRotation => "VEC4 of floats, or of normalized bytes or shorts",
        }
    }
}

fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

fn component_name(c: ComponentType) -> &'static str {
    match c {
        ComponentType::I8 => "byte",
        ComponentType::U8 => "unsigned byte",
        ComponentType::I16 => "short",
        ComponentType::U16 => "unsigned short",
        ComponentType::U32 => "unsigned int",
        ComponentType::F32 => "float",
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

/// Components per element.
pub(super) fn width(t: Type) -> usize {
    match t {
        Type::Scalar => 1,
        Type::Vec2 => 2,
        Type::Vec3 => 3,
        Type::Vec4 | Type::Mat2 => 4,
        Type::Mat3 => 9,
        Type::Mat4 => 16,
    }
}

/// One component at the start of `bytes` (little-endian), normalised as §3.11 defines when
/// `normalized`: `max(c / 127, -1)`, `c / 255`, `max(c / 32767, -1)`, `c / 65535`.
fn component(bytes: &[u8], c: ComponentType, normalized: bool) -> f64 {
    let raw = match c {
        ComponentType::I8 => f64::from(bytes[0] as i8),
        ComponentType::U8 => f64::from(bytes[0]),
        ComponentType::I16 => f64::from(i16::from_le_bytes([bytes[0], bytes[1]])),
        ComponentType::U16 => f64::from(u16::from_le_bytes([bytes[0], bytes[1]])),
        ComponentType::U32 => f64::from(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])),
        ComponentType::F32 => f64::from(f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])),
    };
    if !normalized {
        return raw;
    }
    match c {
        ComponentType::I8 => (raw / 127.0).max(-1.0),
        ComponentType::U8 => raw / 255.0,
        ComponentType::I16 => (raw / 32767.0).max(-1.0),
        ComponentType::U16 => raw / 65535.0,
        ComponentType::U32 | ComponentType::F32 => raw,
    }
}

/// An accessor's declaration, checked against one use.
struct Layout {
    index: usize,
    kind: Type,
    component: ComponentType,
    normalized: bool,
    count: usize,
}

impl Layout {
    fn element_size(&self) -> usize {
        width(self.kind) * component_size(self.component)
    }
}

/// Reads accessors out of a document's buffers.
pub(super) struct Accessors<'d, 'b> {
    pub(super) root: &'d gltf::json::Root,
    pub(super) buffers: &'d Buffers<'b>,
}

impl Accessors<'_, '_> {
    /// The accessor `index`, its existence checked.
    fn get(&self, index: usize) -> Result<&gltf::json::Accessor, String> {
        self.root
            .accessors
            .get(index)
            .ok_or_else(|| format!("accessor {index} does not exist (the file has {})", self.root.accessors.len()))
    }

    /// The element count `index` declares (no data read).
    pub(super) fn count(&self, index: usize) -> Result<usize, String> {
        Ok(self.get(index)?.count.0 as usize)
    }

    /// The element type `index` declares, checked against `use_`.
    fn layout(&self, index: usize, use_: Use) -> Result<Layout, String> {
        let accessor = self.get(index)?;
        let Checked::Valid(kind) = accessor.type_ else {
            return Err(format!("accessor {index} has a type glTF does not define"));
        };
        let Checked::Valid(GenericComponentType(component)) = accessor.component_type else {
            return Err(format!("accessor {index} has a componentType glTF does not define"));
        };
        let normalized = accessor.normalized;
        if normalized && matches!(component, ComponentType::U32 | ComponentType::F32) {
            return Err(format!(
                "accessor {index} is normalized {}s: only bytes and shorts can be",
                component_name(component)
            ));
        }
        if !use_.types().contains(&kind) || !use_.takes(component, normalized) {
            return Err(format!(
                "accessor {index} holds {} {} of {}s, which {} cannot be (glTF allows {})",
                if normalized { "normalized" } else { "plain" },
                type_name(kind),
                component_name(component),
                use_.name(),
                use_.allowed()
            ));
        }
        let count = usize::try_from(accessor.count.0).map_err(|_| format!("accessor {index}'s count is too large"))?;
        Ok(Layout { index, kind, component, normalized, count })
    }

    /// The accessor's components, `count × width` values in element order, with sparse
    /// substitutions made. Float data must be finite.
    pub(super) fn read(&self, index: usize, use_: Use) -> Result<(Vec<f64>, usize), String> {
        let layout = self.layout(index, use_)?;
        let accessor = self.get(index)?;
        let n = width(layout.kind);
        let total = layout.count.checked_mul(n).ok_or_else(|| format!("accessor {index}'s count is too large"))?;
        // The bytes are checked before anything is allocated: a dense accessor's count is
        // bounded by its view; a sparse one without a view declares its zeros, so its size is
        // checked against the memory.
        let dense = match accessor.buffer_view {
            Some(view) => {
                let offset = accessor.byte_offset.map_or(0, |o| o.0);
                Some(self.elements(view.value(), offset, layout.count, &layout, true)?)
            }
            None => {
                let bytes = (total as u64).saturating_mul(8);
                crate::memory::ensure_available(
                    bytes,
                    &format!("accessor {index}'s {} elements", layout.count),
                    "the file declares more than a mesh can hold",
                )
                .map_err(|e| e.to_string())?;
                None
            }
        };
        let mut values = vec![0.0; total];
        if let Some((bytes, stride)) = dense {
            decode(bytes, stride, &layout, &mut values);
        }
        if let Some(sparse) = &accessor.sparse {
            self.substitute(sparse, &layout, &mut values)?;
        }
        if layout.component == ComponentType::F32
            && let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(format!("accessor {index}: element {} is not finite ({})", k / n, values[k]));
            }
        Ok((values, n))
    }

    /// Triangle-corner indices.
    pub(super) fn read_indices(&self, index: usize) -> Result<Vec<u32>, String> {
        let (values, _) = self.read(index, Use::Indices)?;
        Ok(values.into_iter().map(|v| v as u32).collect())
    }

    /// The bytes of `count` elements of `layout` at `offset` in buffer view `view`, and the
    /// stride between them (the view's `byteStride`, or the element size when tightly
    /// packed or when `strided` is false, as sparse data always is).
    fn elements(
        &self,
        view: usize,
        offset: u64,
        count: usize,
        layout: &Layout,
        strided: bool,
    ) -> Result<(&[u8], usize), String> {
        let a = layout.index;
        let (bytes, declared_stride) = self.buffers.view(self.root, view).map_err(|m| format!("accessor {a}: {m}"))?;
        let size = layout.element_size();
        let stride = match declared_stride.filter(|_| strided) {
            Some(s) if s < size => {
                return Err(format!(
                    "accessor {a}'s elements are {size} bytes but buffer view {view}'s byteStride is {s}: the elements would overlap"
                ));
            }
            Some(s) => s,
            None => size,
        };
        let needed = match count.checked_sub(1) {
            None => Some(0),
            Some(last) => (last as u64).checked_mul(stride as u64).and_then(|b| b.checked_add(size as u64)),
        };
        let end = needed.and_then(|n| n.checked_add(offset));
        match end {
            Some(end) if end <= bytes.len() as u64 => Ok((&bytes[offset as usize..end as usize], stride)),
            _ => Err(format!(
                "accessor {a} needs {count} elements of {size} bytes every {stride} from byte {offset} of buffer view {view}, which has {} bytes",
                bytes.len()
            )),
        }
    }

    /// Sparse substitutions (§3.6.2.3): strictly increasing indices below the count, each
    /// replacing one element.
    fn substitute(
        &self,
        sparse: &gltf::json::accessor::sparse::Sparse,
        layout: &Layout,
        values: &mut [f64],
    ) -> Result<(), String> {
        let a = layout.index;
        let count = usize::try_from(sparse.count.0).unwrap_or(usize::MAX);
        if count == 0 || count > layout.count {
            return Err(format!("accessor {a}: {count} sparse substitutions for {} elements", layout.count));
        }
        let Checked::Valid(index_type) = sparse.indices.component_type else {
            return Err(format!("accessor {a}: the sparse indices' componentType is not one glTF allows"));
        };
        let index_layout = Layout { index: a, kind: Type::Scalar, component: index_type.0, normalized: false, count };
        if !Use::Indices.takes(index_layout.component, false) {
            return Err(format!(
                "accessor {a}: sparse indices of {}s (glTF allows unsigned bytes, shorts or ints)",
                component_name(index_layout.component)
            ));
        }
        let (index_bytes, index_stride) = self.elements(
            sparse.indices.buffer_view.value(),
            sparse.indices.byte_offset.0,
            count,
            &index_layout,
            false,
        )?;
        let (value_bytes, value_stride) =
            self.elements(sparse.values.buffer_view.value(), sparse.values.byte_offset.0, count, layout, false)?;
        let n = width(layout.kind);
        let size = component_size(layout.component);
        let mut previous: Option<usize> = None;
        for k in 0..count {
            let target = component(&index_bytes[k * index_stride..], index_layout.component, false) as usize;
            if target >= layout.count || previous.is_some_and(|p| target <= p) {
                return Err(format!(
                    "accessor {a}: sparse index {k} is {target}; they must increase strictly and stay below {}",
                    layout.count
                ));
            }
            previous = Some(target);
            let element = &value_bytes[k * value_stride..];
            for c in 0..n {
                values[target * n + c] = component(&element[c * size..], layout.component, layout.normalized);
            }
        }
        Ok(())
    }
}

fn decode(bytes: &[u8], stride: usize, layout: &Layout, values: &mut [f64]) {
    let n = width(layout.kind);
    let size = component_size(layout.component);
    for (e, element) in values.chunks_exact_mut(n).enumerate() {
        let at = &bytes[e * stride..];
        for (c, value) in element.iter_mut().enumerate() {
            *value = component(&at[c * size..], layout.component, layout.normalized);
        }
    }
}
