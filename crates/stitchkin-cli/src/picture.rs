//! Writing a picture: the SVG as drawn by the library, or — for `-o FILE.png`
//! — the same drawing rasterised by resvg (feature `png`, on by default).
//!
//! The PNG uses the DejaVu Sans font embedded in the binary
//! (assets/fonts/, Bitstream Vera licence), so it looks the same on a
//! machine without fonts; the SVG itself names the generic `sans-serif`
//! family and needs no font to be written.

use std::path::{Path, PathBuf};

use stitchkin::error::{Error, ParamError};

/// What a picture file is, from its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Format {
    Svg,
    Png,
}

/// The format of `-o PATH`: `.svg` or `.png` (any case); no `-o` is SVG on
/// stdout.
pub(crate) fn format_of(out: Option<&PathBuf>) -> Result<Format, Error> {
    let Some(path) = out else { return Ok(Format::Svg) };
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("svg") => Ok(Format::Svg),
        Some("png") => Ok(Format::Png),
        _ => Err(Error::Param(ParamError::general(
            format!("cannot tell the picture format of `{}` (in -o)", path.display()),
            Some("end the file name in .svg (vector, scalable) or .png (raster, 2 pixels per SVG unit)".into()),
        ))),
    }
}

/// The format `-o` asks for, checked before any work: a known extension,
/// an existing folder, and no PNG of an animation (a PNG would show one
/// frame and silently drop the motion).
pub(crate) fn check_output(out: Option<&PathBuf>, animated: bool) -> Result<Format, Error> {
    if let Some(path) = out {
        stitchkin::output::check_folder(path)?;
    }
    match format_of(out)? {
        Format::Png if animated => Err(Error::Param(ParamError::general(
            "an animation cannot be written as PNG (in -o)",
            Some("write it as .svg (it plays in any browser), or leave out --animate for a still PNG".into()),
        ))),
        f => Ok(f),
    }
}

/// Writes `svg` to `out` (stdout when `None`) as SVG or, for a `.png` name,
/// as PNG (see [`check_output`]).
/// A file written says so on stderr.
pub(crate) fn emit_picture(svg: &str, out: Option<&PathBuf>, animated: bool) -> Result<(), Error> {
    let bytes = match (check_output(out, animated)?, out) {
        (Format::Png, Some(path)) => svg_to_png(svg, path)?,
        _ => svg.as_bytes().to_vec(),
    };
    crate::common::emit(&bytes, out)
}

/// Pixels per SVG unit of the PNG: 2, crisp on high-density screens and in
/// print at the charts' 900 px width.
#[cfg(feature = "png")]
pub(crate) const PNG_SCALE: f32 = 2.0;

#[cfg(feature = "png")]
fn svg_to_png(svg: &str, path: &Path) -> Result<Vec<u8>, Error> {
    let internal = |what: String| Error::Internal(format!("cannot draw {} as PNG: {what}", path.display()));
    rasterize(svg)
        .map_err(internal)?
        .encode_png()
        .map_err(|e| internal(format!("PNG encoding failed ({e})")))
}

/// The SVG drawn on white at [`PNG_SCALE`] pixels per unit.
#[cfg(feature = "png")]
fn rasterize(svg: &str) -> Result<resvg::tiny_skia::Pixmap, String> {
    use resvg::{tiny_skia, usvg};
    static DEJAVU_SANS: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

    let mut opt = usvg::Options::default();
    let fonts = opt.fontdb_mut();
    fonts.load_font_data(DEJAVU_SANS.to_vec());
    fonts.set_sans_serif_family("DejaVu Sans");
    let tree = usvg::Tree::from_str(svg, &opt).map_err(|e| format!("the SVG does not parse ({e})"))?;
    let size = tree.size();
    let (w, h) = (
        (size.width() * PNG_SCALE).ceil() as u32,
        (size.height() * PNG_SCALE).ceil() as u32,
    );
    let mut pixmap = tiny_skia::Pixmap::new(w, h).ok_or_else(|| format!("{w}×{h} px is not a picture size"))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(PNG_SCALE, PNG_SCALE),
        &mut pixmap.as_mut(),
    );
    Ok(pixmap)
}

#[cfg(not(feature = "png"))]
fn svg_to_png(_svg: &str, path: &Path) -> Result<Vec<u8>, Error> {
    Err(Error::Param(ParamError::general(
        format!(
            "this stitchkin was built without PNG output, so it cannot write `{}`",
            path.display()
        ),
        Some("write .svg instead, or rebuild with the default features (feature `png`)".into()),
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_follows_the_extension() {
        assert_eq!(format_of(None).unwrap(), Format::Svg);
        assert_eq!(format_of(Some(&PathBuf::from("a/b.SVG"))).unwrap(), Format::Svg);
        assert_eq!(format_of(Some(&PathBuf::from("b.png"))).unwrap(), Format::Png);
        let err = format_of(Some(&PathBuf::from("b.jpg"))).unwrap_err().to_string();
        assert!(err.contains("b.jpg"), "{err}");
        assert!(format_of(Some(&PathBuf::from("noext"))).is_err());
    }

    #[cfg(feature = "png")]
    #[test]
    fn png_has_the_svg_size_times_the_scale_and_draws_text() {
        let svg = |body: &str| {
            format!(
                r#"<svg xmlns="http://www.w3.org/2000/svg" width="120" height="40" viewBox="0 0 120 40">{body}</svg>"#
            )
        };
        let png = svg_to_png(&svg(""), Path::new("t.png")).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        // IHDR width and height, big-endian, at bytes 16..24.
        assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 240);
        assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), 80);
        let dark = |body: &str| {
            rasterize(&svg(body))
                .unwrap()
                .pixels()
                .iter()
                .filter(|p| p.red() < 128)
                .count()
        };
        assert_eq!(dark(""), 0, "the background is white");
        // The embedded font draws the glyphs (a missing font draws nothing).
        let text = dark(r#"<text x="5" y="30" font-family="sans-serif" font-size="24">P, mm</text>"#);
        assert!(text > 150, "{text} dark pixels");
    }
}
