//! SVG to pixels with `resvg`, text in the DejaVu Sans font shipped inside the `dejavu` crate
//! (loaded once), and PNG encoding and decoding.

use std::sync::{Arc, OnceLock};

use resvg::tiny_skia::Pixmap;
use resvg::usvg;

use crate::error::ViewError;

/// The font database: DejaVu Sans regular and bold, nothing from the system.
fn fonts() -> Arc<usvg::fontdb::Database> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = usvg::fontdb::Database::new();
            db.load_font_data(dejavu::sans::regular().to_vec());
            db.load_font_data(dejavu::sans::bold().to_vec());
            db.set_sans_serif_family(crate::style::FONT);
            Arc::new(db)
        })
        .clone()
}

/// Parses SVG text into the tree the rasteriser draws, text laid out in the embedded font (its
/// nodes' bounding boxes are where things are drawn: for tools and tests).
pub fn parse(svg: &str) -> Result<usvg::Tree, ViewError> {
    let options = usvg::Options {
        fontdb: fonts(),
        font_family: crate::style::FONT.to_string(),
        ..usvg::Options::default()
    };
    usvg::Tree::from_str(svg, &options).map_err(|e| ViewError::Render(e.to_string()))
}

/// Rasterises SVG text into a pixmap (premultiplied RGBA) of the SVG's own size.
pub fn render_pixmap(svg: &str) -> Result<Pixmap, ViewError> {
    let tree = parse(svg)?;
    let size = tree.size().to_int_size();
    let mut pixmap = Pixmap::new(size.width(), size.height())
        .ok_or_else(|| ViewError::Render(format!("empty picture size {size:?}")))?;
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    Ok(pixmap)
}

/// A pixmap's width, height and straight (not premultiplied) RGBA bytes, row-major.
fn straight_rgba(pixmap: &Pixmap) -> (u32, u32, Vec<u8>) {
    let (w, h) = (pixmap.width(), pixmap.height());
    let mut out = Vec::with_capacity((w * h * 4) as usize);
    for p in pixmap.pixels() {
        let c = p.demultiply();
        out.extend_from_slice(&[c.red(), c.green(), c.blue(), c.alpha()]);
    }
    (w, h, out)
}

/// Rasterises SVG text: width, height and straight (not premultiplied) RGBA bytes, row-major.
pub fn render_rgba(svg: &str) -> Result<(u32, u32, Vec<u8>), ViewError> {
    Ok(straight_rgba(&render_pixmap(svg)?))
}

/// Rasterises SVG text into PNG bytes (RGB when the picture is opaque, as ours are).
pub fn render_png(svg: &str) -> Result<Vec<u8>, ViewError> {
    let (w, h, rgba) = render_rgba(svg)?;
    encode_png(w, h, &rgba)
}

/// Encodes straight RGBA pixels as PNG with the fast DEFLATE of the `png` crate (a report
/// writes hundreds of pictures: its default level took a third of each picture's time).
pub fn encode_png(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>, ViewError> {
    let err = |e: png::EncodingError| ViewError::Render(e.to_string());
    let opaque = rgba.chunks_exact(4).all(|p| p[3] == 255);
    let rgb: Vec<u8>;
    let (colour, data) = if opaque {
        rgb = rgba
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        (png::ColorType::Rgb, rgb.as_slice())
    } else {
        (png::ColorType::Rgba, rgba)
    };
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(colour);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        let mut writer = encoder.write_header().map_err(err)?;
        writer.write_image_data(data).map_err(err)?;
        writer.finish().map_err(err)?;
    }
    Ok(out)
}

/// Decodes PNG bytes (a picture or a browser's screenshot): width, height, straight RGBA.
pub fn decode_png(bytes: &[u8]) -> Result<(u32, u32, Vec<u8>), ViewError> {
    let pixmap = Pixmap::decode_png(bytes).map_err(|e| ViewError::Render(e.to_string()))?;
    Ok(straight_rgba(&pixmap))
}
