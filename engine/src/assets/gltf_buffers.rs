//! A glTF file's URIs, buffers and buffer views, for the importer and the texture readers:
//! percent-decoding, capped buffer loading and bounds-checked buffer view bytes.

use crate::limits::FileKind;
use base64::Engine;
use std::path::Path;

/// The bytes behind a glTF URI: a base64 `data:` URI, or a percent-encoded path relative
/// to `base`, read as a file of `kind` (a regular file within its cap).
pub(super) fn read_uri(base: &Path, uri: &str, kind: FileKind) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let payload = rest
            .split_once(";base64,")
            .map(|(_, p)| p)
            .ok_or("a data URI that is not base64")?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| format!("bad base64 data URI: {e}"));
    }
    if uri.contains(':') {
        return Err(format!("unsupported URI scheme in {uri}"));
    }
    let path = base.join(percent_decoded(uri));
    crate::files::read(&path, kind).map_err(|e| e.to_string())
}

/// Loads every buffer of `document`: the GLB binary chunk, a base64 `data:` URI, or a file
/// beside the document read with [`crate::files::read`] (a regular file, capped as
/// [`FileKind::Buffer`]). A buffer shorter than its `byteLength` is an error. A
/// placeholder for `EXT_meshopt_compression`'s decoded views (marked `fallback`, or
/// without a URI where the binary chunk is taken or absent in a file that uses the
/// extension) is zeros of its `byteLength`, for [`super::meshopt::decompress`] to fill.
pub(super) fn load_buffers(
    document: &gltf::Document,
    base: &Path,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<gltf::buffer::Data>, String> {
    let cap = FileKind::Buffer.cap();
    let meshopt = document
        .extensions_used()
        .any(|e| e == super::meshopt::EXTENSION);
    document
        .buffers()
        .map(|buffer| {
            let at = format!("buffer {}", buffer.index());
            let declared = buffer.length();
            if declared as u64 > cap {
                return Err(format!(
                    "{at}: byteLength {declared} is over the {} cap",
                    crate::limits::bytes_text(cap)
                ));
            }
            let placeholder = super::meshopt::is_fallback(&buffer)
                || (meshopt
                    && blob.is_none()
                    && matches!(buffer.source(), gltf::buffer::Source::Bin));
            let bytes = match buffer.source() {
                _ if placeholder => vec![0; declared],
                gltf::buffer::Source::Bin => blob
                    .take()
                    .ok_or_else(|| format!("{at}: the file has no binary chunk"))?,
                gltf::buffer::Source::Uri(uri) => {
                    read_uri(base, uri, FileKind::Buffer).map_err(|e| format!("{at}: {e}"))?
                }
            };
            if bytes.len() < declared {
                return Err(format!(
                    "{at}: {} bytes, shorter than its byteLength {declared}",
                    bytes.len()
                ));
            }
            Ok(gltf::buffer::Data(bytes))
        })
        .collect()
}

/// The files a glTF document (its JSON, `json`) in folder `base` reads beside itself:
/// its buffers' and images' relative URIs, percent-decoded, in the document's order
/// (`data:` URIs and the GLB binary chunk are inside the file). `None` when `json` is
/// not a glTF document.
pub fn external_files(json: &[u8], base: &Path) -> Option<Vec<std::path::PathBuf>> {
    let document = gltf::Gltf::from_slice_without_validation(json)
        .ok()?
        .document;
    let buffers = document.buffers().filter_map(|b| match b.source() {
        gltf::buffer::Source::Uri(uri) => Some(uri.to_string()),
        gltf::buffer::Source::Bin => None,
    });
    let images = document.images().filter_map(|i| match i.source() {
        gltf::image::Source::Uri { uri, .. } => Some(uri.to_string()),
        gltf::image::Source::View { .. } => None,
    });
    Some(
        buffers
            .chain(images)
            .filter(|uri| !uri.contains(':'))
            .map(|uri| base.join(percent_decoded(&uri)))
            .collect(),
    )
}

/// A URI's `%XX` escapes decoded (glTF URIs are percent-encoded); malformed escapes stay.
pub(super) fn percent_decoded(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(b)) => {
                out.push(b);
                i += 3;
            }
            (c, _) => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The bytes of a buffer view, if it lies inside its buffer.
pub(super) fn view_bytes<'a>(
    view: &gltf::buffer::View,
    buffers: &'a [gltf::buffer::Data],
) -> Option<&'a [u8]> {
    let data = buffers.get(view.buffer().index())?;
    let end = view.offset().checked_add(view.length())?;
    data.0.get(view.offset()..end)
}

/// Checks that an accessor's elements lie inside its buffer view and buffer (the glTF
/// reader would otherwise panic on a short buffer).
pub(super) fn check_accessor(
    accessor: &gltf::Accessor,
    buffers: &[gltf::buffer::Data],
) -> std::result::Result<(), String> {
    let name = format!("accessor {}", accessor.index());
    if let Some(view) = accessor.view() {
        let bytes = view_bytes(&view, buffers).ok_or(format!(
            "{name}: buffer view {} lies outside its buffer",
            view.index()
        ))?;
        let element = accessor.size();
        let stride = view.stride().unwrap_or(element).max(element);
        let needed = match accessor.count() {
            0 => 0,
            n => (n - 1)
                .checked_mul(stride)
                .and_then(|x| x.checked_add(element))
                .and_then(|x| x.checked_add(accessor.offset()))
                .ok_or(format!("{name}: size overflows"))?,
        };
        if needed > bytes.len() {
            return Err(format!(
                "{name} needs {needed} bytes but its buffer view holds {}",
                bytes.len()
            ));
        }
    }
    if let Some(sparse) = accessor.sparse() {
        for view in [sparse.indices().view(), sparse.values().view()] {
            if view_bytes(&view, buffers).is_none() {
                return Err(format!(
                    "{name}: sparse buffer view {} lies outside its buffer",
                    view.index()
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_uris_are_errors() {
        let base = Path::new("/nonexistent");
        assert!(
            read_uri(base, "missing.png", FileKind::Texture)
                .unwrap_err()
                .contains("missing.png")
        );
        assert!(read_uri(base, "data:image/png;base64,@@@", FileKind::Texture).is_err());
        assert!(read_uri(base, "https://example.com/a.png", FileKind::Texture).is_err());
        assert_eq!(
            read_uri(base, "data:image/png;base64,AAEC", FileKind::Texture).ok(),
            Some(vec![0, 1, 2])
        );
        assert_eq!(percent_decoded("a%20b%zz"), "a b%zz");
    }
}
