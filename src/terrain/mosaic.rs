//! A GDAL Virtual Raster (VRT, <https://gdal.org/drivers/raster/vrt.html>) that stitches
//! a plan's tiles into one raster: GIS tools (`gdalinfo`, `gdal_translate`, QGIS) open the
//! mosaic as one heightmap. Tiles share their border rows and columns, which hold the same
//! values, so overlapping destination rectangles agree. Headerless tiles (RAW16, F32) get a
//! small VRT each (`VRTRawRasterBand`) that says how their bytes are laid out; 16-bit bands
//! carry `Offset` and `Scale`, so the heights in world units are `offset + value × scale`.

use std::fmt::Write as _;

use super::sidecar::{Quantisation, WorldPlacement};
use super::stream::StreamFormat;

/// One tile's place in the mosaic.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MosaicTile {
    /// The tile's file, relative to the mosaic's folder.
    pub file: String,
    /// Its first column in the mosaic.
    pub x: u64,
    /// Its first row in the mosaic.
    pub y: u64,
    /// Its columns.
    pub columns: usize,
    /// Its rows.
    pub rows: usize,
}

/// GDAL's name of the format's sample type.
fn data_type(format: StreamFormat) -> &'static str {
    if format.is_16_bit() { "UInt16" } else { "Float32" }
}

/// Escapes text for an XML attribute or element.
fn xml(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;").replace('\'', "&apos;")
}

/// The file a mosaic names for a tile: the tile itself, or for a headerless tile its
/// descriptor (`NAME.vrt` beside it, see [`raw_descriptor`]).
pub fn source_of(tile_file: &str, format: StreamFormat) -> String {
    match format {
        StreamFormat::Raw16 | StreamFormat::F32 => format!("{tile_file}.vrt"),
        _ => tile_file.to_string(),
    }
}

/// The VRT of a mosaic `columns` × `rows` points of `format` tiles. The geotransform puts
/// point (0, 0) at `world` (x, y), one pixel per point (pixel centres on the points).
pub fn vrt(
    columns: u64,
    rows: u64,
    format: StreamFormat,
    quantisation: Option<Quantisation>,
    world: WorldPlacement,
    tiles: &[MosaicTile],
) -> String {
    let kind = data_type(format);
    let mut text = String::new();
    let _ = writeln!(text, r#"<VRTDataset rasterXSize="{columns}" rasterYSize="{rows}">"#);
    let (sx, sy) = (world.spacing_x, world.spacing_y);
    let _ = writeln!(
        text,
        "  <GeoTransform>{:e}, {sx:e}, 0, {:e}, 0, {sy:e}</GeoTransform>",
        world.x - sx / 2.0,
        world.y - sy / 2.0
    );
    let _ = writeln!(text, r#"  <VRTRasterBand dataType="{kind}" band="1">"#);
    if let Some(q) = quantisation {
        let _ = writeln!(text, "    <Offset>{:e}</Offset>\n    <Scale>{:e}</Scale>", q.offset, q.scale);
    }
    for tile in tiles {
        let (w, h) = (tile.columns, tile.rows);
        let _ = write!(
            text,
            concat!(
                "    <SimpleSource>\n",
                "      <SourceFilename relativeToVRT=\"1\">{}</SourceFilename>\n",
                "      <SourceBand>1</SourceBand>\n",
                "      <SourceProperties RasterXSize=\"{w}\" RasterYSize=\"{h}\" DataType=\"{kind}\" BlockXSize=\"{w}\" BlockYSize=\"1\"/>\n",
                "      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"{w}\" ySize=\"{h}\"/>\n",
                "      <DstRect xOff=\"{x}\" yOff=\"{y}\" xSize=\"{w}\" ySize=\"{h}\"/>\n",
                "    </SimpleSource>\n"
            ),
            xml(&source_of(&tile.file, format)),
            w = w,
            h = h,
            kind = kind,
            x = tile.x,
            y = tile.y
        );
    }
    text.push_str("  </VRTRasterBand>\n</VRTDataset>\n");
    text
}

/// The VRT describing one headerless tile (`file_name`, in the same folder): row-major
/// little-endian samples of `format`, no header.
pub fn raw_descriptor(file_name: &str, columns: usize, rows: usize, format: StreamFormat) -> String {
    let bytes = if format.is_16_bit() { 2 } else { 4 };
    format!(
        concat!(
            "<VRTDataset rasterXSize=\"{w}\" rasterYSize=\"{h}\">\n",
            "  <VRTRasterBand dataType=\"{kind}\" band=\"1\" subClass=\"VRTRawRasterBand\">\n",
            "    <SourceFilename relativeToVRT=\"1\">{file}</SourceFilename>\n",
            "    <ImageOffset>0</ImageOffset>\n",
            "    <PixelOffset>{bytes}</PixelOffset>\n",
            "    <LineOffset>{line}</LineOffset>\n",
            "    <ByteOrder>LSB</ByteOrder>\n",
            "  </VRTRasterBand>\n",
            "</VRTDataset>\n"
        ),
        w = columns,
        h = rows,
        kind = data_type(format),
        file = xml(file_name),
        bytes = bytes,
        line = bytes * columns
    )
}
