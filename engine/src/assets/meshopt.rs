//! `EXT_meshopt_compression`: buffer views stored compressed by meshoptimizer's codecs
//! (Kapoulkine & St. Pierre, Khronos 2021, "EXT_meshopt_compression", its appendices A
//! and B), decoded here into the places their uncompressed bytes would have, before any
//! accessor is read. Files written by `gltfpack` use it for vertex, index and animation
//! data, often with `KHR_mesh_quantization`.
//!
//! A compressed view names a second buffer, range, element size (`byteStride`) and
//! element count, a **mode** and, for attributes, a **filter**:
//!
//! - `ATTRIBUTES` (header `0xa0`): blocks of up to 256 elements; each byte position of
//!   the element is stored separately, as zigzag-coded byte deltas from the previous
//!   element (the first from a baseline at the stream's end), 16 elements to a group,
//!   each group 0, 2, 4 or 8 bits a delta (2 and 4 with an escape to a whole byte);
//! - `TRIANGLES` (header `0xe1`): one code byte a triangle, reusing edges and vertices
//!   from two 16-entry FIFOs of recent ones, with the rest of each index in LEB128
//!   varints coding zigzag deltas;
//! - `INDICES` (header `0xd1`): zigzag deltas in varints against two running baselines.
//!
//! The filters turn decoded attributes into their final form: `OCTAHEDRAL` (unit
//! vectors from octahedral coordinates), `QUATERNION` (unit quaternions from three
//! components and the index of the largest) and `EXPONENTIAL` (floats from an 8-bit
//! exponent and a 24-bit mantissa).
//!
//! The uncompressed buffer a compressed view belongs to may be a placeholder without data
//! (marked `fallback`): the buffer loader (`gltf_buffers::load_buffers`) allocates it,
//! zeroed, at its declared length (within the buffer cap). A view is decoded only where
//! it lies inside its loaded buffer, and the codecs refuse element counts their stream
//! is too short to hold, so nothing larger than the file's buffers is allocated. Every
//! malformed stream is an error naming its buffer view, never a panic.

/// The extension's name.
pub const EXTENSION: &str = "EXT_meshopt_compression";

/// Whether `buffer` is marked as a placeholder (`fallback`) whose bytes come only from
/// compressed views (`load_buffers` also treats a buffer without a URI as one where the
/// binary chunk is taken or absent).
pub(super) fn is_fallback(buffer: &gltf::Buffer) -> bool {
    buffer
        .extension_value(EXTENSION)
        .and_then(|e| e.get("fallback"))
        .and_then(|f| f.as_bool())
        .unwrap_or(false)
}

/// How a compressed view's bytes are coded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Attributes,
    Triangles,
    Indices,
}

/// What is done to decoded attributes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
}

/// A compressed buffer view's extension object.
#[derive(Clone, Copy, Debug)]
struct Compressed {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: Mode,
    filter: Filter,
}

impl Compressed {
    /// Reads and checks the extension object `ext` of a view of `view_length` bytes
    /// (and its own `byteStride`, if any), by the specification's rules.
    fn parse(
        ext: &gltf::json::Value,
        view_length: usize,
        view_stride: Option<usize>,
    ) -> Result<Compressed, String> {
        let integer = |key: &str, default: Option<usize>| match ext.get(key) {
            None => default.ok_or(format!("it has no {key}")),
            Some(v) => v
                .as_u64()
                .and_then(|x| usize::try_from(x).ok())
                .ok_or(format!("its {key} is not a whole number ({v})")),
        };
        let text = |key: &str, default: Option<&'static str>| match ext.get(key) {
            None => default
                .map(str::to_string)
                .ok_or(format!("it has no {key}")),
            Some(v) => v
                .as_str()
                .map(str::to_string)
                .ok_or(format!("its {key} is not a string ({v})")),
        };
        let mode = match text("mode", None)?.as_str() {
            "ATTRIBUTES" => Mode::Attributes,
            "TRIANGLES" => Mode::Triangles,
            "INDICES" => Mode::Indices,
            other => return Err(format!("unknown mode {other}")),
        };
        let filter = match text("filter", Some("NONE"))?.as_str() {
            "NONE" => Filter::None,
            "OCTAHEDRAL" => Filter::Octahedral,
            "QUATERNION" => Filter::Quaternion,
            "EXPONENTIAL" => Filter::Exponential,
            other => return Err(format!("unknown filter {other}")),
        };
        let c = Compressed {
            buffer: integer("buffer", None)?,
            offset: integer("byteOffset", Some(0))?,
            length: integer("byteLength", None)?,
            stride: integer("byteStride", None)?,
            count: integer("count", None)?,
            mode,
            filter,
        };
        let stride_ok = match (c.mode, c.filter) {
            (Mode::Attributes, Filter::None | Filter::Exponential) => {
                c.stride.is_multiple_of(4) && (4..=256).contains(&c.stride)
            }
            (Mode::Attributes, Filter::Octahedral) => c.stride == 4 || c.stride == 8,
            (Mode::Attributes, Filter::Quaternion) => c.stride == 8,
            (_, Filter::None) => c.stride == 2 || c.stride == 4,
            _ => false,
        };
        if !stride_ok {
            return Err(format!(
                "byteStride {} does not suit mode {:?} with filter {:?}",
                c.stride, c.mode, c.filter
            ));
        }
        if c.mode == Mode::Triangles && !c.count.is_multiple_of(3) {
            return Err(format!("{} indices do not make whole triangles", c.count));
        }
        if view_stride.is_some_and(|s| s != c.stride) {
            return Err(format!(
                "its byteStride {} differs from the view's {view_stride:?}",
                c.stride
            ));
        }
        if c.stride.checked_mul(c.count) != Some(view_length) {
            return Err(format!(
                "{} elements of {} bytes do not fill the view's {view_length} bytes",
                c.count, c.stride
            ));
        }
        Ok(c)
    }
}

/// Decodes every compressed buffer view of `document` into its place in `buffers` (the
/// view's own buffer and range); returns how many there were. An error names the view.
pub(super) fn decompress(
    document: &gltf::Document,
    buffers: &mut [gltf::buffer::Data],
) -> Result<usize, String> {
    let mut decoded = 0;
    for view in document.views() {
        let Some(ext) = view.extension_value(EXTENSION) else {
            continue;
        };
        let at = format!("buffer view {}", view.index());
        let c = Compressed::parse(ext, view.length(), view.stride())
            .map_err(|e| format!("{at}: {EXTENSION}: {e}"))?;
        // The view's place, inside a loaded (capped) buffer, bounds what is decoded.
        let inside = buffers.get(view.buffer().index()).is_some_and(|b| {
            view.offset()
                .checked_add(view.length())
                .is_some_and(|end| end <= b.0.len())
        });
        if !inside {
            return Err(format!("{at} lies outside its buffer"));
        }
        let source = buffers
            .get(c.buffer)
            .and_then(|b| b.0.get(c.offset..c.offset.checked_add(c.length)?))
            .ok_or(format!(
                "{at}: {EXTENSION}: its {} bytes at {} lie outside buffer {}",
                c.length, c.offset, c.buffer
            ))?;
        let bytes = decode(source, &c).map_err(|e| format!("{at}: {EXTENSION}: {e}"))?;
        let target = buffers
            .get_mut(view.buffer().index())
            .and_then(|b| {
                let end = view.offset().checked_add(view.length())?;
                b.0.get_mut(view.offset()..end)
            })
            .ok_or(format!("{at} lies outside its buffer"))?;
        target.copy_from_slice(&bytes);
        decoded += 1;
    }
    Ok(decoded)
}

/// The view's bytes from its compressed stream `data`.
fn decode(data: &[u8], c: &Compressed) -> Result<Vec<u8>, String> {
    match c.mode {
        Mode::Attributes => {
            let mut out = decode_vertex_buffer(data, c.count, c.stride)?;
            match c.filter {
                Filter::None => {}
                Filter::Octahedral => octahedral_filter(&mut out, c.stride),
                Filter::Quaternion => quaternion_filter(&mut out),
                Filter::Exponential => exponential_filter(&mut out),
            }
            Ok(out)
        }
        Mode::Triangles => decode_index_buffer(data, c.count, c.stride),
        Mode::Indices => decode_index_sequence(data, c.count, c.stride),
    }
}

/// A cursor over a stream that ends at `end`: every read is checked.
struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    end: usize,
}

impl Reader<'_> {
    fn bytes(&mut self, n: usize) -> Result<&[u8], String> {
        let stop = self.pos.checked_add(n).filter(|&s| s <= self.end);
        let stop = stop.ok_or("the stream ends early")?;
        let out = &self.data[self.pos..stop];
        self.pos = stop;
        Ok(out)
    }

    fn byte(&mut self) -> Result<u8, String> {
        Ok(self.bytes(1)?[0])
    }

    /// An unsigned LEB128 integer of at most 32 bits ("varint-7").
    fn varint(&mut self) -> Result<u32, String> {
        let mut value = 0u32;
        for shift in (0..35).step_by(7) {
            let b = self.byte()?;
            value |= u32::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                return Ok(value);
            }
        }
        Err("a varint longer than 5 bytes".into())
    }
}

/// Zigzag decoding: 0, 1, 2, 3… → 0, −1, 1, −2…
fn unzigzag8(v: u8) -> u8 {
    if v & 1 != 0 { !(v >> 1) } else { v >> 1 }
}

fn unzigzag32(v: u32) -> u32 {
    if v & 1 != 0 { !(v >> 1) } else { v >> 1 }
}

/// Mode 0: `count` elements of `stride` bytes from an attribute stream (header `0xa0`).
pub fn decode_vertex_buffer(data: &[u8], count: usize, stride: usize) -> Result<Vec<u8>, String> {
    if stride == 0 || stride > 256 {
        return Err(format!("element size {stride} is outside 1..256"));
    }
    let tail = stride.max(32);
    if data.first() != Some(&0xa0) {
        return Err("not an attribute stream (header 0xa0)".into());
    }
    if data.len() < 1 + tail {
        return Err("the stream is shorter than its tail".into());
    }
    // Each byte position needs a header byte per 64 elements at least.
    if count.div_ceil(64).saturating_mul(stride) > data.len() {
        return Err(format!(
            "{count} elements cannot fit a {}-byte stream",
            data.len()
        ));
    }
    let mut last = data[data.len() - stride..].to_vec();
    let mut out = vec![0u8; count.checked_mul(stride).ok_or("the size overflows")?];
    let mut r = Reader {
        data,
        pos: 1,
        end: data.len() - tail,
    };
    let block_max = ((8192 / stride) & !15).min(256);
    let mut deltas = [0u8; 256];
    let mut start = 0;
    while start < count {
        let block = block_max.min(count - start);
        let groups = block.div_ceil(16);
        for (k, previous) in last.iter_mut().enumerate() {
            let header = r.bytes(groups.div_ceil(4))?.to_vec();
            for g in 0..groups {
                let bits = (header[g / 4] >> ((g % 4) * 2)) & 3;
                decode_group(&mut r, bits, &mut deltas[g * 16..g * 16 + 16])?;
            }
            let mut p = *previous;
            for (i, delta) in deltas[..block].iter().enumerate() {
                p = p.wrapping_add(unzigzag8(*delta));
                out[(start + i) * stride + k] = p;
            }
            *previous = p;
        }
        start += block;
    }
    Ok(out)
}

/// One group of 16 byte deltas (zigzag-coded) in the encoding `bits`: 0 all zero, 1 and
/// 2 two and four bits each (most significant first) with all-ones escaping to a byte
/// that follows, 3 a byte each.
fn decode_group(r: &mut Reader, bits: u8, out: &mut [u8]) -> Result<(), String> {
    match bits {
        0 => out.fill(0),
        3 => out.copy_from_slice(r.bytes(16)?),
        _ => {
            let width = if bits == 1 { 2 } else { 4 };
            let packed = r.bytes(16 * width / 8)?.to_vec();
            let sentinel = (1u8 << width) - 1;
            for (i, o) in out.iter_mut().enumerate() {
                let bit = i * width;
                let shift = 8 - width - bit % 8;
                let d = (packed[bit / 8] >> shift) & sentinel;
                *o = if d == sentinel { r.byte()? } else { d };
            }
        }
    }
    Ok(())
}

/// Writes index `value` as `size` (2 or 4) little-endian bytes; a 2-byte index must fit.
fn put_index(out: &mut Vec<u8>, value: u32, size: usize) -> Result<(), String> {
    if size == 2 {
        let v = u16::try_from(value).map_err(|_| format!("index {value} does not fit 16 bits"))?;
        out.extend_from_slice(&v.to_le_bytes());
    } else {
        out.extend_from_slice(&value.to_le_bytes());
    }
    Ok(())
}

/// The triangle codec's state: the edge and vertex FIFOs (16 entries each, entry i
/// counting back from the most recent, 0), the next new index and the last explicit one.
struct TriangleState {
    edges: [(u32, u32); 16],
    edge_at: usize,
    vertices: [u32; 16],
    vertex_at: usize,
    next: u32,
    last: u32,
}

impl TriangleState {
    fn edge(&self, i: usize) -> (u32, u32) {
        self.edges[(self.edge_at + 15 - i) & 15]
    }

    fn vertex(&self, i: usize) -> u32 {
        self.vertices[(self.vertex_at + 15 - i) & 15]
    }

    fn push_edge(&mut self, a: u32, b: u32) {
        self.edges[self.edge_at & 15] = (a, b);
        self.edge_at += 1;
    }

    fn push_vertex(&mut self, v: u32) {
        self.vertices[self.vertex_at & 15] = v;
        self.vertex_at += 1;
    }

    /// `next`, then one more.
    fn take_next(&mut self) -> u32 {
        self.next = self.next.wrapping_add(1);
        self.next.wrapping_sub(1)
    }

    /// An index coded explicitly: a zigzag delta from `last` in a varint.
    fn explicit(&mut self, r: &mut Reader) -> Result<u32, String> {
        self.last = self.last.wrapping_add(unzigzag32(r.varint()?));
        Ok(self.last)
    }

    /// One triangle from its code byte (and the stream's extra bytes, and the table
    /// `aux`).
    fn triangle(&mut self, code: u8, r: &mut Reader, aux: &[u8]) -> Result<[u32; 3], String> {
        if code < 0xf0 {
            // A recent edge and a third vertex: new, recent, next to `last`, or explicit.
            let (a, b) = self.edge(usize::from(code >> 4));
            let y = code & 15;
            let c = match y {
                0 => self.take_next(),
                1..=0xc => self.vertex(usize::from(y)),
                0xd | 0xe => {
                    self.last = if y == 0xd {
                        self.last.wrapping_sub(1)
                    } else {
                        self.last.wrapping_add(1)
                    };
                    self.last
                }
                _ => self.explicit(r)?,
            };
            self.push_edge(c, b);
            self.push_edge(a, c);
            if !(1..=0xc).contains(&y) {
                self.push_vertex(c);
            }
            return Ok([a, b, c]);
        }
        // Three vertices: from the table (0xfY) or from an extra byte (0xfe, 0xff), each
        // new, recent or (with an extra byte, 0xf) explicit.
        let extra = code >= 0xfe;
        let zw = if extra {
            let zw = r.byte()?;
            if zw == 0 {
                self.next = 0;
            }
            zw
        } else {
            aux[usize::from(code & 15)]
        };
        let a = if code == 0xff {
            self.explicit(r)?
        } else {
            self.take_next()
        };
        let (z, w) = (zw >> 4, zw & 15);
        let mut other = |f: u8, state: &mut TriangleState| match f {
            0 => Ok(state.take_next()),
            15 if extra => state.explicit(r),
            _ => Ok(state.vertex(usize::from(f) - 1)),
        };
        let b = other(z, self)?;
        let c = other(w, self)?;
        self.push_edge(b, a);
        self.push_edge(c, b);
        self.push_edge(a, c);
        self.push_vertex(a);
        let fresh = |f: u8| f == 0 || (f == 15 && extra);
        if fresh(z) {
            self.push_vertex(b);
        }
        if fresh(w) {
            self.push_vertex(c);
        }
        Ok([a, b, c])
    }
}

/// Mode 1: `count` triangle-list indices of `size` bytes (2 or 4) from a triangle stream
/// (header `0xe1`).
pub fn decode_index_buffer(data: &[u8], count: usize, size: usize) -> Result<Vec<u8>, String> {
    if !count.is_multiple_of(3) {
        return Err(format!("{count} indices do not make whole triangles"));
    }
    if data.first() != Some(&0xe1) {
        return Err("not a triangle stream (header 0xe1)".into());
    }
    let triangles = count / 3;
    if data.len() < 1 + triangles + 16 {
        return Err("the stream is shorter than its codes and table".into());
    }
    let aux = &data[data.len() - 16..];
    let mut r = Reader {
        data,
        pos: 1 + triangles,
        end: data.len() - 16,
    };
    let mut state = TriangleState {
        edges: [(0, 0); 16],
        edge_at: 0,
        vertices: [0; 16],
        vertex_at: 0,
        next: 0,
        last: 0,
    };
    let mut out = Vec::with_capacity(count * size);
    for &code in &data[1..1 + triangles] {
        for v in state.triangle(code, &mut r, aux)? {
            put_index(&mut out, v, size)?;
        }
    }
    if r.pos != r.end {
        return Err(format!("{} byte(s) left over", r.end - r.pos));
    }
    Ok(out)
}

/// Mode 2: `count` indices of `size` bytes (2 or 4) from an index sequence (header
/// `0xd1`).
pub fn decode_index_sequence(data: &[u8], count: usize, size: usize) -> Result<Vec<u8>, String> {
    if data.first() != Some(&0xd1) {
        return Err("not an index sequence (header 0xd1)".into());
    }
    // A byte per index at least, and the tail.
    if data.len() < count.saturating_add(1 + 4) {
        return Err(format!(
            "{count} indices cannot fit a {}-byte stream",
            data.len()
        ));
    }
    let mut r = Reader {
        data,
        pos: 1,
        end: data.len() - 4,
    };
    let mut last = [0u32; 2];
    let mut out = Vec::with_capacity(count * size);
    for _ in 0..count {
        let v = r.varint()?;
        let baseline = (v & 1) as usize;
        let delta = unzigzag32(v >> 1);
        last[baseline] = last[baseline].wrapping_add(delta);
        put_index(&mut out, last[baseline], size)?;
    }
    Ok(out)
}

/// Filter 1 on elements of four 8-bit (`stride` 4) or 16-bit (8) signed components: x
/// and y in octahedral coordinates over the third, 1.0 in the vector's own precision,
/// become a unit vector's snorm components; the fourth passes through.
fn octahedral_filter(bytes: &mut [u8], stride: usize) {
    let wide = stride == 8;
    let max = if wide { 32767.0 } else { 127.0 };
    for element in bytes.chunks_exact_mut(stride) {
        let get = |i: usize| {
            if wide {
                f32::from(i16::from_le_bytes([element[2 * i], element[2 * i + 1]]))
            } else {
                f32::from(element[i] as i8)
            }
        };
        let one = get(2);
        let (mut x, mut y) = (get(0) / one, get(1) / one);
        let z = 1.0 - x.abs() - y.abs();
        let t = z.min(0.0);
        x -= t.copysign(x);
        y -= t.copysign(y);
        let len = (x * x + y * y + z * z).sqrt();
        for (i, v) in [x, y, z].into_iter().enumerate() {
            let q = (v / len * max).round();
            let q = if q.is_finite() { q } else { 0.0 };
            if wide {
                element[2 * i..2 * i + 2].copy_from_slice(&(q as i16).to_le_bytes());
            } else {
                element[i] = q as i8 as u8;
            }
        }
    }
}

/// Filter 2 on elements of four 16-bit components: three quaternion components scaled by
/// √2 over 1.0 in their own precision (the fourth, whose two low bits name the largest
/// component, omitted and positive) become the whole unit quaternion's snorm16s.
fn quaternion_filter(bytes: &mut [u8]) {
    for element in bytes.chunks_exact_mut(8) {
        let get = |i: usize| i16::from_le_bytes([element[2 * i], element[2 * i + 1]]);
        let last = get(3);
        let one = f32::from(last | 3);
        let scale = std::f32::consts::FRAC_1_SQRT_2 / one;
        let (x, y, z) = (
            f32::from(get(0)) * scale,
            f32::from(get(1)) * scale,
            f32::from(get(2)) * scale,
        );
        let w = (1.0 - x * x - y * y - z * z).max(0.0).sqrt();
        let largest = (last & 3) as usize;
        for (k, v) in [(1, x), (2, y), (3, z), (0, w)] {
            let q = (v * 32767.0).round();
            let q = if q.is_finite() { q as i16 } else { 0 };
            let i = (largest + k) % 4;
            element[2 * i..2 * i + 2].copy_from_slice(&q.to_le_bytes());
        }
    }
}

/// Filter 3 on 32-bit words: an 8-bit signed exponent e over a 24-bit signed mantissa m
/// become the float 2^e · m.
fn exponential_filter(bytes: &mut [u8]) {
    for word in bytes.chunks_exact_mut(4) {
        let v = i32::from_le_bytes([word[0], word[1], word[2], word[3]]);
        let e = v >> 24;
        let m = (v << 8) >> 8;
        let f = (e as f32).exp2() * m as f32;
        word.copy_from_slice(&f.to_le_bytes());
    }
}

#[cfg(test)]
mod tests {
    //! The streams and their decoded bytes are meshoptimizer's own decoder test vectors
    //! (zeux/meshoptimizer, `js/meshopt_decoder.test.js`), encoded by its encoder.
    use super::*;

    fn u32s(bytes: &[u8]) -> Vec<u32> {
        bytes
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }

    fn u16s(bytes: &[u8]) -> Vec<u16> {
        bytes
            .chunks_exact(2)
            .map(|c| u16::from_le_bytes([c[0], c[1]]))
            .collect()
    }

    /// A stream of `head` followed by zeros up to `len` bytes and then `end`.
    fn stream(head: &[u8], len: usize, end: &[u8]) -> Vec<u8> {
        let mut s = head.to_vec();
        s.resize(len - end.len(), 0);
        s.extend_from_slice(end);
        s
    }

    #[test]
    fn attributes_decode_as_the_reference_encoder_wrote_them() {
        let encoded = stream(
            &[
                0xa0, 0x01, 0x3f, 0x00, 0x00, 0x00, 0x58, 0x57, 0x58, 0x01, 0x26, 0x00, 0x00, 0x00,
                0x01, 0x0c, 0x00, 0x00, 0x00, 0x58, 0x01, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                0x00, 0x01, 0x3f, 0x00, 0x00, 0x00, 0x17, 0x18, 0x17, 0x01, 0x26, 0x00, 0x00, 0x00,
                0x01, 0x0c, 0x00, 0x00, 0x00, 0x17, 0x01, 0x08,
            ],
            85,
            &[],
        );
        let expected = [
            0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 44, 1, 0, 0, 0, 0, 0, 0, 244, 1, 0, 0, 0, 0, 44, 1,
            0, 0, 0, 0, 0, 0, 244, 1, 44, 1, 44, 1, 0, 0, 0, 0, 244, 1, 244, 1,
        ];
        assert_eq!(decode_vertex_buffer(&encoded, 4, 12), Ok(expected.to_vec()));
        // Groups of 2-, 4- and 8-bit deltas (header bits 1, 2, 3).
        let more = stream(
            &[
                0xa0, 0x00, 0x01, 0x2a, 0xaa, 0xaa, 0xaa, 0x02, 0x04, 0x44, 0x44, 0x44, 0x44, 0x44,
                0x44, 0x44, 0x03, 0x00, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10,
                0x10, 0x10, 0x10, 0x10, 0x10,
            ],
            65,
            &[],
        );
        let expected: Vec<u8> = (0..16u8).flat_map(|i| [0, i, 2 * i, 8 * i]).collect();
        assert_eq!(decode_vertex_buffer(&more, 16, 4), Ok(expected));
        let twos = stream(
            &[
                0xa0, 0x02, 0x08, 0x88, 0x88, 0x88, 0x88, 0x88, 0x88, 0x88, 0x02, 0x0a, 0xaa, 0xaa,
                0xaa, 0xaa, 0xaa, 0xaa, 0xaa, 0x02, 0x0c, 0xcc, 0xcc, 0xcc, 0xcc, 0xcc, 0xcc, 0xcc,
                0x02, 0x0e, 0xee, 0xee, 0xee, 0xee, 0xee, 0xee, 0xee,
            ],
            69,
            &[],
        );
        let expected: Vec<u8> = (0..16u8)
            .flat_map(|i| [4 * i, 5 * i, 6 * i, 7 * i])
            .collect();
        assert_eq!(decode_vertex_buffer(&twos, 16, 4), Ok(expected));
    }

    #[test]
    fn triangles_decode_as_the_reference_encoder_wrote_them() {
        let aux = [
            0x00, 0x76, 0x87, 0x56, 0x67, 0x78, 0xa9, 0x86, 0x65, 0x89, 0x68, 0x98, 0x01, 0x69,
            0x00, 0x00,
        ];
        let with = |head: &[u8]| [head, &aux[..]].concat();
        // Codes reading the tables, the edge FIFO, an explicit index, last − 1 and a
        // restart of `next`.
        let v1 = with(&[0xe1, 0xf0, 0x10, 0xfe, 0x1f, 0x3d, 0x00, 0x0a]);
        let out = decode_index_buffer(&v1, 15, 4).expect("decodes");
        assert_eq!(u32s(&out), [0, 1, 2, 2, 1, 3, 0, 1, 2, 2, 1, 5, 2, 1, 4]);
        let more = with(&[
            0xe1, 0xf0, 0x10, 0xfe, 0xff, 0xf0, 0x0c, 0xff, 0x02, 0x02, 0x02,
        ]);
        let expected = [0, 1, 2, 2, 1, 3, 4, 6, 5, 7, 8, 9];
        let out = decode_index_buffer(&more, 12, 4).expect("decodes");
        assert_eq!(u32s(&out), expected);
        let out = decode_index_buffer(&more, 12, 2).expect("decodes");
        assert_eq!(u16s(&out), expected.map(|i| i as u16));
        let edges = with(&[0xe1, 0xf0, 0x20, 0x30, 0x40]);
        let out = decode_index_buffer(&edges, 12, 4).expect("decodes");
        assert_eq!(u32s(&out), [0, 1, 2, 1, 0, 3, 2, 1, 4, 0, 2, 5]);
    }

    #[test]
    fn index_sequences_decode_as_the_reference_encoder_wrote_them() {
        let encoded = [
            0xd1, 0x00, 0x04, 0xcd, 0x01, 0x04, 0x07, 0x98, 0x1f, 0x00, 0x00, 0x00, 0x00,
        ];
        let out = decode_index_sequence(&encoded, 6, 4).expect("decodes");
        assert_eq!(u32s(&out), [0, 1, 51, 2, 49, 1000]);
        // 1000 fits 16 bits; the two baselines run apart.
        let out = decode_index_sequence(&encoded, 6, 2).expect("decodes");
        assert_eq!(u16s(&out), [0, 1, 51, 2, 49, 1000]);
    }

    #[test]
    fn filters_decode_as_the_reference_encoder_wrote_them() {
        let oct8 = stream(
            &[
                0xa0, 0x01, 0x07, 0x00, 0x00, 0x00, 0x1e, 0x01, 0x3f, 0x00, 0x00, 0x00, 0x8b, 0x8c,
                0xfd, 0x00, 0x01, 0x26,
            ],
            53,
            &[0x01, 0x7f, 0x00],
        );
        let c = |stride, filter| Compressed {
            buffer: 0,
            offset: 0,
            length: 0,
            stride,
            count: 4,
            mode: Mode::Attributes,
            filter,
        };
        let out = decode(&oct8, &c(4, Filter::Octahedral)).expect("decodes");
        assert_eq!(
            out,
            [0, 1, 127, 0, 0, 159, 82, 1, 255, 1, 127, 0, 1, 130, 241, 1]
        );
        let head12 = [
            0xa0, 0x01, 0x0f, 0x00, 0x00, 0x00, 0x3d, 0x5a, 0x01, 0x0f, 0x00, 0x00, 0x00, 0x0e,
            0x0d, 0x01, 0x3f, 0x00, 0x00, 0x00, 0x9a, 0x99, 0x26, 0x01, 0x3f, 0x00, 0x00, 0x00,
            0x0e, 0x0d, 0x0a, 0x00, 0x00, 0x01,
        ];
        let oct12 = stream(
            &[&head12[..], &[0x26]].concat(),
            71,
            &[0x01, 0x00, 0xff, 0x07, 0x00, 0x00],
        );
        let out = decode(&oct12, &c(8, Filter::Octahedral)).expect("decodes");
        assert_eq!(
            u16s(&out),
            [
                0, 16, 32767, 0, 0, 32621, 3088, 1, 32764, 16, 471, 0, 307, 28541, 16093, 1
            ]
        );
        let quat12 = stream(
            &[&head12[..], &[0x2a]].concat(),
            71,
            &[0x01, 0x00, 0x00, 0x00, 0xfc, 0x07],
        );
        let out = decode(&quat12, &c(8, Filter::Quaternion)).expect("decodes");
        assert_eq!(
            u16s(&out),
            [
                32767, 0, 11, 0, 0, 25013, 0, 21166, 11, 0, 23504, 22830, 158, 14715, 0, 29277
            ]
        );
        let exp = stream(
            &[0xa0],
            49,
            &[
                0x03, 0x00, 0x00, 0xff, 0xf7, 0xff, 0xff, 0x02, 0xff, 0xff, 0x7f, 0xfe,
            ],
        );
        let one = Compressed {
            count: 1,
            ..c(16, Filter::Exponential)
        };
        let out = decode(&exp, &one).expect("decodes");
        assert_eq!(u32s(&out), [0, 0x3fc0_0000, 0xc210_0000, 0x49ff_fffe]);
    }

    #[test]
    fn extension_objects_are_checked_by_the_specification_rules() {
        let parse = |ext: gltf::json::Value, length, stride| {
            Compressed::parse(&ext, length, stride).map(|c| (c.mode, c.filter))
        };
        let ext = |mode: &str, filter: &str, stride: usize, count: usize| {
            serde_json::json!({"buffer": 0, "byteLength": 10, "byteStride": stride,
                "count": count, "mode": mode, "filter": filter})
        };
        let ok = parse(ext("ATTRIBUTES", "OCTAHEDRAL", 8, 3), 24, Some(8));
        assert_eq!(ok, Ok((Mode::Attributes, Filter::Octahedral)));
        assert!(parse(ext("TRIANGLES", "NONE", 2, 6), 12, None).is_ok());
        for (bad, length, stride, needle) in [
            (ext("ATTRIBUTES", "NONE", 6, 2), 12, None, "does not suit"),
            (
                ext("ATTRIBUTES", "QUATERNION", 4, 2),
                8,
                None,
                "does not suit",
            ),
            (
                ext("TRIANGLES", "OCTAHEDRAL", 4, 3),
                12,
                None,
                "does not suit",
            ),
            (ext("TRIANGLES", "NONE", 4, 4), 16, None, "whole triangles"),
            (ext("INDICES", "NONE", 4, 4), 20, None, "do not fill"),
            (ext("ATTRIBUTES", "NONE", 8, 2), 16, Some(12), "differs"),
            (ext("LINES", "NONE", 4, 4), 16, None, "unknown mode"),
            (ext("INDICES", "SQUARE", 4, 4), 16, None, "unknown filter"),
            (
                serde_json::json!({"mode": "INDICES"}),
                16,
                None,
                "no buffer",
            ),
        ] {
            let err = parse(bad, length, stride).expect_err(needle);
            assert!(err.contains(needle), "{err}");
        }
    }

    #[test]
    fn broken_streams_are_errors() {
        // Wrong headers, truncations and left-over bytes: errors, never panics.
        assert!(decode_vertex_buffer(&[0xa1; 64], 4, 12).is_err());
        assert!(decode_vertex_buffer(&[0xa0; 20], 4, 12).is_err());
        let mut truncated = vec![0xa0, 0xff];
        truncated.resize(40, 0);
        assert!(decode_vertex_buffer(&truncated, 16, 4).is_err());
        assert!(decode_index_buffer(&[0xe0; 20], 3, 4).is_err());
        assert!(decode_index_buffer(&[0xe1, 0xff], 3, 4).is_err());
        assert!(decode_index_buffer(&[0xe1, 0xf0, 7], 3, 4).is_err());
        let mut extra = vec![0xe1, 0xf0, 0x42];
        extra.resize(19, 0);
        assert_eq!(
            decode_index_buffer(&extra, 3, 4),
            Err("1 byte(s) left over".into())
        );
        assert!(decode_index_sequence(&[0xd1, 0x80, 0x80, 0, 0, 0, 0], 2, 4).is_err());
        assert!(
            decode_index_sequence(&[0xd1, 0xff, 0xff, 0xff, 0xff, 0xff, 1, 0, 0, 0, 0], 1, 4)
                .is_err()
        );
        // Element counts the stream cannot hold are refused before anything is allocated.
        let mut short = vec![0xa0];
        short.resize(64, 0);
        assert!(decode_vertex_buffer(&short, usize::MAX / 2, 4).is_err());
        assert!(decode_index_sequence(&[0xd1, 0, 0, 0, 0], 1 << 40, 4).is_err());
        assert!(decode_index_buffer(&[0xe1; 40], usize::MAX - 2, 4).is_err());
        // An index beyond 16 bits in a 2-byte view.
        let big = [0xd1, 0x80, 0x80, 0x10, 0, 0, 0, 0];
        assert!(decode_index_sequence(&big, 1, 4).is_ok());
        assert!(decode_index_sequence(&big, 1, 2).is_err());
        for random in 0..64u32 {
            let bytes: Vec<u8> = (0..40u32)
                .map(|i| (i.wrapping_mul(2_654_435_761) ^ random.wrapping_mul(40_503)) as u8)
                .collect();
            for head in [0xa0, 0xe1, 0xd1] {
                let s = [&[head][..], &bytes[..]].concat();
                let _ = decode_vertex_buffer(&s, 20, 8);
                let _ = decode_index_buffer(&s, 30, 2);
                let _ = decode_index_sequence(&s, 30, 4);
            }
        }
    }
}
