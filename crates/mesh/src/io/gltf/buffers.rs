//! The bytes of a glTF file's buffers (the GLB BIN chunk, `data:` URIs, files next to the
//! model) and its accessors read from them, every byte range checked ([`Source`]).

use super::uri::{data_uri, percent_decode};
use crate::error::MeshError;
use ::gltf::accessor::DataType;
use std::path::{Path, PathBuf};

/// A buffer file handed over in memory: its name next to the `.gltf` (as the URI names it,
/// percent-decoded) and its bytes.
pub(crate) type SideBuffer<'a> = (&'a str, &'a [u8]);

/// The bytes of `buffer`: the GLB BIN chunk, a `data:` URI, the `side` buffer when the URI names
/// it, or a file next to the glTF; checked against the declared `byteLength`.
fn load_buffer(
    buffer: &::gltf::Buffer,
    bin: Option<&[u8]>,
    side: Option<SideBuffer>,
    dir: &Path,
    files: &mut Vec<PathBuf>,
) -> Result<Vec<u8>, String> {
    let data = match buffer.source() {
        ::gltf::buffer::Source::Bin => match bin {
            Some(b) if buffer.index() == 0 => b.to_vec(),
            _ => {
                return Err(format!(
                    "buffer {} has no uri and the file has no GLB BIN chunk for it",
                    buffer.index()
                ));
            }
        },
        ::gltf::buffer::Source::Uri(uri) => match data_uri(uri) {
            Some(r) => r?,
            None => {
                let name = percent_decode(uri);
                if let Some((_, bytes)) = side.filter(|(n, _)| *n == name) {
                    bytes.to_vec()
                } else {
                    // The containment rule: a regular file inside the glTF's folder, at most
                    // the bytes the buffer declares.
                    crate::io::contain::resolve(dir, dir, &name)
                        .and_then(|file| {
                            let bytes =
                                crate::io::contain::read_prefix(&file, buffer.length() as u64);
                            files.push(file);
                            bytes
                        })
                        .map_err(|e| format!("buffer {} ({uri}) not read: {e}", buffer.index()))?
                }
            }
        },
    };
    if data.len() < buffer.length() {
        return Err(format!(
            "buffer {} declares {} bytes but has {} (truncated?)",
            buffer.index(),
            buffer.length(),
            data.len()
        ));
    }
    Ok(data)
}

/// The decoded document with its buffers, for reading accessors.
pub(super) struct Source<'a> {
    /// The validated document.
    pub(super) doc: &'a ::gltf::Document,
    /// Each buffer's bytes, or why they could not be read.
    buffers: Vec<Result<Vec<u8>, String>>,
    /// The file, for the messages.
    pub(super) path: &'a Path,
}

impl<'a> Source<'a> {
    /// `doc` with the bytes of each of its buffers ([`load_buffer`]; the files read are added to
    /// `files`); `path` is the glTF file, whose folder `dir` is.
    pub(super) fn load(
        doc: &'a ::gltf::Document,
        path: &'a Path,
        bin: Option<&[u8]>,
        side: Option<SideBuffer>,
        dir: &Path,
        files: &mut Vec<PathBuf>,
    ) -> Self {
        let buffers = doc
            .buffers()
            .map(|b| load_buffer(&b, bin, side, dir, files))
            .collect();
        Source { doc, buffers, path }
    }
}

impl Source<'_> {
    pub(super) fn error(
        &self,
        location: impl Into<String>,
        message: impl Into<String>,
    ) -> MeshError {
        MeshError::parse(self.path, location, message)
    }

    /// The bytes of buffer view `view`, range-checked against its buffer.
    pub(super) fn view_bytes(&self, view: &::gltf::buffer::View) -> Result<&[u8], MeshError> {
        let b = view.buffer().index();
        let data = self.buffers[b]
            .as_ref()
            .map_err(|e| self.error(format!("buffer {b}"), e.clone()))?;
        let (start, length) = (view.offset(), view.length());
        start
            .checked_add(length)
            .and_then(|end| data.get(start..end))
            .ok_or_else(|| {
                self.error(
                    format!("buffer view {}", view.index()),
                    format!(
                        "bytes {start}..{} lie outside buffer {b}, which has {} bytes",
                        start.saturating_add(length),
                        data.len()
                    ),
                )
            })
    }

    /// The bytes of buffer view `view` and its stride, checked to hold `count` elements of
    /// `element` bytes from `offset` (strided by the view's `byteStride`, or packed).
    fn range<'v>(
        &'v self,
        what: &str,
        view: &::gltf::buffer::View,
        offset: usize,
        count: usize,
        element: usize,
    ) -> Result<(&'v [u8], usize), MeshError> {
        let data = self.view_bytes(view)?;
        let stride = view.stride().unwrap_or(element);
        if stride < element {
            return Err(self.error(
                what,
                format!(
                    "byteStride {stride} of buffer view {} is smaller than an element ({element} \
                     bytes)",
                    view.index()
                ),
            ));
        }
        if count == 0 {
            return Ok((data, stride));
        }
        let end = (count - 1)
            .checked_mul(stride)
            .and_then(|n| n.checked_add(offset))
            .and_then(|n| n.checked_add(element));
        match end {
            Some(end) if end <= data.len() => Ok((data, stride)),
            _ => Err(self.error(
                what,
                format!(
                    "{count} elements of {element} bytes from byte {offset} (stride {stride}) do \
                     not fit in buffer view {}, which has {} bytes",
                    view.index(),
                    data.len()
                ),
            )),
        }
    }

    /// Calls `f` with the bytes of each of `count` elements of `element` bytes at `offset` in
    /// `view` ([`Source::range`]).
    fn elements(
        &self,
        what: &str,
        view: &::gltf::buffer::View,
        offset: usize,
        count: usize,
        element: usize,
        mut f: impl FnMut(usize, &[u8]),
    ) -> Result<(), MeshError> {
        let (data, stride) = self.range(what, view, offset, count, element)?;
        for i in 0..count {
            let at = offset + i * stride;
            f(i, &data[at..at + element]);
        }
        Ok(())
    }

    /// Checks, before anything is allocated for them, that the `count` elements of `element`
    /// bytes of `accessor` exist: in its buffer view, or (without one: zeros, or sparse values
    /// only) no more than the file's buffers could describe, so that a count in the JSON alone
    /// cannot ask for any amount of memory.
    fn check_count(
        &self,
        accessor: &::gltf::Accessor,
        what: &str,
        element: usize,
    ) -> Result<(), MeshError> {
        let count = accessor.count();
        match accessor.view() {
            Some(view) => self
                .range(what, &view, accessor.offset(), count, element)
                .map(|_| ()),
            None => {
                let bytes: usize = self.buffers.iter().flatten().map(Vec::len).sum();
                if count > bytes.max(1 << 24) {
                    Err(self.error(
                        what,
                        format!(
                            "{count} elements without a buffer view, more than the file's buffers \
                             ({bytes} bytes) could hold"
                        ),
                    ))
                } else {
                    Ok(())
                }
            }
        }
    }

    /// The values of `accessor` as `f32`s, `dims` per element (normalized integers mapped to
    /// [0, 1] or [-1, 1] as the glTF specification says; other integers as they are), with
    /// sparse substitution.
    pub(super) fn floats(
        &self,
        accessor: &::gltf::Accessor,
        what: &str,
        dims: &[usize],
    ) -> Result<(Vec<f32>, usize), MeshError> {
        let what = format!("accessor {} ({what})", accessor.index());
        let n = accessor.dimensions().multiplicity();
        if !dims.contains(&n) {
            return Err(self.error(
                &what,
                format!(
                    "{:?} elements; expected {}",
                    accessor.dimensions(),
                    dims.iter()
                        .map(|d| format!("{d} components"))
                        .collect::<Vec<_>>()
                        .join(" or ")
                ),
            ));
        }
        let ty = accessor.data_type();
        let normalized = accessor.normalized();
        let size = ty.size();
        let count = accessor.count();
        self.check_count(accessor, &what, n * size)?;
        let mut out = vec![0f32; count * n];
        let decode = |bytes: &[u8], out: &mut [f32]| {
            for (k, o) in out.iter_mut().enumerate() {
                *o = component(&bytes[k * size..(k + 1) * size], ty, normalized);
            }
        };
        if let Some(view) = accessor.view() {
            self.elements(&what, &view, accessor.offset(), count, n * size, |i, e| {
                decode(e, &mut out[i * n..(i + 1) * n])
            })?;
        }
        if let Some(sparse) = accessor.sparse() {
            let indices = self.sparse_indices(&sparse, &what, count)?;
            let values = sparse.values();
            self.elements(
                &what,
                &values.view(),
                values.offset(),
                indices.len(),
                n * size,
                |i, e| {
                    let at = indices[i] as usize;
                    decode(e, &mut out[at * n..(at + 1) * n])
                },
            )?;
        }
        Ok((out, n))
    }

    /// The indices of a sparse accessor, checked against `count`.
    fn sparse_indices(
        &self,
        sparse: &::gltf::accessor::sparse::Sparse,
        what: &str,
        count: usize,
    ) -> Result<Vec<u32>, MeshError> {
        use ::gltf::accessor::sparse::IndexType;
        let indices = sparse.indices();
        let ty = match indices.index_type() {
            IndexType::U8 => DataType::U8,
            IndexType::U16 => DataType::U16,
            IndexType::U32 => DataType::U32,
        };
        let mut out = Vec::new();
        self.elements(
            what,
            &indices.view(),
            indices.offset(),
            sparse.count(),
            ty.size(),
            |_, e| out.push(unsigned(e, ty)),
        )?;
        if let Some(&bad) = out.iter().find(|&&i| i as usize >= count) {
            return Err(self.error(
                what,
                format!("sparse index {bad} is beyond its {count} elements"),
            ));
        }
        Ok(out)
    }

    /// The values of an index accessor (unsigned byte, short or int scalars).
    pub(super) fn indices(
        &self,
        accessor: &::gltf::Accessor,
        what: &str,
    ) -> Result<Vec<u32>, MeshError> {
        let what = format!("accessor {} ({what})", accessor.index());
        let ty = accessor.data_type();
        if accessor.dimensions() != ::gltf::accessor::Dimensions::Scalar
            || !matches!(ty, DataType::U8 | DataType::U16 | DataType::U32)
        {
            return Err(self.error(
                &what,
                format!(
                    "indices must be unsigned byte, short or int scalars, not {:?} {:?}",
                    ty,
                    accessor.dimensions()
                ),
            ));
        }
        self.check_count(accessor, &what, ty.size())?;
        let mut out = vec![0u32; accessor.count()];
        if let Some(view) = accessor.view() {
            self.elements(
                &what,
                &view,
                accessor.offset(),
                out.len(),
                ty.size(),
                |i, e| out[i] = unsigned(e, ty),
            )?;
        }
        if let Some(sparse) = accessor.sparse() {
            let at = self.sparse_indices(&sparse, &what, out.len())?;
            let values = sparse.values();
            self.elements(
                &what,
                &values.view(),
                values.offset(),
                at.len(),
                ty.size(),
                |i, e| out[at[i] as usize] = unsigned(e, ty),
            )?;
        }
        Ok(out)
    }
}

/// An unsigned integer component (little-endian).
fn unsigned(bytes: &[u8], ty: DataType) -> u32 {
    match ty {
        DataType::U8 => u32::from(bytes[0]),
        DataType::U16 => u32::from(u16::from_le_bytes([bytes[0], bytes[1]])),
        _ => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
    }
}

/// One component as `f32` (little-endian), normalized integers scaled as the glTF
/// specification says.
fn component(bytes: &[u8], ty: DataType, normalized: bool) -> f32 {
    match ty {
        DataType::F32 => f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
        DataType::I8 => {
            let v = f32::from(bytes[0] as i8);
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        DataType::U8 => {
            let v = f32::from(bytes[0]);
            if normalized { v / 255.0 } else { v }
        }
        DataType::I16 => {
            let v = f32::from(i16::from_le_bytes([bytes[0], bytes[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = f32::from(u16::from_le_bytes([bytes[0], bytes[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        DataType::U32 => {
            let v = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f32;
            if normalized { v / u32::MAX as f32 } else { v }
        }
    }
}
