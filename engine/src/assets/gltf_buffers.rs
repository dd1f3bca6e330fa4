//! A glTF file's URIs and buffer views, for the importer and the texture readers:
//! percent-decoding and bounds-checked buffer view bytes.

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
