#include "nestwalk/terrain/terrain_imagery.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/gdal_util.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <gdalwarper.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>
#include <system_error>
#include <type_traits>

namespace nestwalk::terrain {
namespace {

namespace fs = std::filesystem;

/// One run of output samples along one axis, read with one floating-point source window: output
/// indices out0 + m * outStep (m < count) sample the source at winOff + (m + 0.5) * winSize / count.
struct AxisRead {
  int out0 = 0, outStep = 1, count = 0;
  double winOff = 0, winSize = 0;  // source pixels
  int intOff = 0, intSize = 0;     // the integer window GDAL is given: it holds the floating one
};

/// Fills in the integer window of `r` over an axis of `size` pixels and appends it. GDAL's RasterIO
/// copies pixels without resampling when the integer window is as large as the buffer on both axes,
/// whatever the floating-point window says; so an axis whose floating window is not exactly the
/// integer one gets an integer window one pixel larger than its buffer (or is split in two where the
/// window already spans the whole axis).
void addAxisRead(std::vector<AxisRead>& reads, AxisRead r, int size) {
  r.winOff = std::clamp(r.winOff, 0.0, double(size));
  r.winSize = std::clamp(r.winSize, 0.0, double(size) - r.winOff);
  const double end = r.winOff + r.winSize;
  int off = int(std::floor(r.winOff));
  int stop = std::min(size, int(std::ceil(end)));
  if (stop <= off) stop = std::min(size, off + 1), off = stop - 1;
  const bool exact = r.winOff == double(off) && r.winSize == double(r.count) && end == double(stop);
  if (!exact && stop - off == r.count) {
    if (stop < size) ++stop;
    else if (off > 0) --off;
    else if (r.count > 1) {
      const int first = r.count / 2;
      const double step = r.winSize / r.count;
      AxisRead a = r, b = r;
      a.count = first;
      a.winSize = step * first;
      b.count = r.count - first;
      b.out0 = r.out0 + first * r.outStep;
      b.winOff = r.winOff + step * first;
      b.winSize = r.winSize - step * first;
      addAxisRead(reads, a, size);
      addAxisRead(reads, b, size);
      return;
    }
    // else: a single pixel on a one-pixel axis: every position in it has that pixel's value.
  }
  r.intOff = off;
  r.intSize = stop - off;
  reads.push_back(r);
}

/// The reads along one axis of `size` source pixels for output samples at source positions
/// p0 + k * step (k < n; pixel i spans [i, i + 1], its centre at i + 0.5). Samples beyond the outer
/// edge are left out (no data); a sample whose footprint (|step| wide) would reach past the edge is
/// read alone, its footprint moved inward to the edge (see the header).
std::vector<AxisRead> planAxis(double p0, double step, int n, int size) {
  std::vector<AxisRead> reads;
  const double a = std::abs(step), tol = kImageryEdgeTolerancePixels;
  // m: position in ascending source order; k: the output index.
  auto indexOf = [&](int m) { return step > 0 ? m : n - 1 - m; };
  auto posOf = [&](int m) { return p0 + indexOf(m) * step; };
  int m0 = 0, m1 = n;
  while (m0 < n && posOf(m0) < -tol) ++m0;
  while (m1 > m0 && posOf(m1 - 1) > size + tol) --m1;
  if (m0 >= m1) return reads;
  const int outStep = step > 0 ? 1 : -1;
  const double footprint = std::min(a, double(size));
  auto single = [&](int m) {
    const double q = posOf(m);
    const double centre = a <= size ? std::clamp(q, 0.5 * a, size - 0.5 * a) : 0.5 * size;
    addAxisRead(reads, AxisRead{indexOf(m), outStep, 1, centre - 0.5 * footprint, footprint, 0, 0}, size);
  };
  int i0 = m0, i1 = m1;  // the interior run: footprints inside the axis
  while (i0 < m1 && posOf(i0) - 0.5 * a < -tol) ++i0;
  while (i1 > i0 && posOf(i1 - 1) + 0.5 * a > size + tol) --i1;
  for (int m = m0; m < i0; ++m) single(m);
  if (i1 > i0)
    addAxisRead(reads, AxisRead{indexOf(i0), outStep, i1 - i0, posOf(i0) - 0.5 * a, (i1 - i0) * a, 0, 0}, size);
  for (int m = std::max(i1, i0); m < m1; ++m) single(m);
  return reads;
}

double byteFrom(double v) { return std::clamp(std::round(v), 0.0, 255.0); }

/// The CRS in `wkt` parsed (nullptr when empty); InputError naming `what` when GDAL cannot read it.
OGRSpatialReferenceH parseCrs(const std::string& wkt, const std::string& what) {
  if (wkt.empty()) return nullptr;
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  if (OSRSetFromUserInput(srs, wkt.c_str()) != OGRERR_NONE) {
    OSRDestroySpatialReference(srs);
    throw InputError(what);
  }
  OSRSetAxisMappingStrategy(srs, OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

struct SrsClose {
  void operator()(OGRSpatialReferenceH srs) const {
    if (srs) OSRDestroySpatialReference(srs);
  }
};
using Srs = std::unique_ptr<std::remove_pointer_t<OGRSpatialReferenceH>, SrsClose>;

struct TransformerClose {
  void operator()(void* t) const {
    if (t) GDALDestroyTransformer(t);
  }
};
using Transformer = std::unique_ptr<void, TransformerClose>;

struct WarpOptionsClose {
  void operator()(GDALWarpOptions* o) const {
    if (o) GDALDestroyWarpOptions(o);
  }
};

struct WarpOperationClose {
  void operator()(void* op) const {
    if (op) GDALDestroyWarpOperation(static_cast<GDALWarpOperationH>(op));
  }
};

}  // namespace

struct TerrainImagery::State {
  std::string path;
  std::vector<std::string> warnings;
  GdalDataset source;
  int cols = 0, rows = 0;
  int colourBands = 1;  // 1 or 3
  int alphaBand = 0;    // band number of the alpha, 0 when none
  double gt[6] = {0, 1, 0, 0, 0, -1};
  bool byteColour = true, byteAlpha = true;
  double colourLo = 0, colourHi = 255;  // non-8-bit colour: the range scaled to 0..255
  double alphaMax = 255;                // non-8-bit alpha: the value that is opaque
  bool reproject = false;
  std::string terrainWkt;
  Transformer toImagery;  // reprojected: map (terrain CRS) -> imagery pixel/line, full resolution
  ImageryExtent extent;
  double pixelSize = 1;
  std::map<int, GdalDataset> overviews;  // reprojected: overview levels opened so far

  GDALDatasetH dataset() const { return static_cast<GDALDatasetH>(source.get()); }

  /// 0..255 from a resampled colour value (NaN stays NaN).
  double colourByte(double v) const {
    if (byteColour) return byteFrom(v);
    if (!(colourHi > colourLo)) return std::isnan(v) ? v : 255.0;
    return byteFrom(255.0 * (v - colourLo) / (colourHi - colourLo));
  }
  double alphaByte(double v) const { return byteAlpha ? byteFrom(v) : byteFrom(255.0 * v / alphaMax); }

  void readSameFrame(double x0, double y0, double sx, double sy, int w, int h, std::vector<std::uint8_t>& out);
  void readReprojected(double x0, double y0, double sx, double sy, int w, int h, std::vector<std::uint8_t>& out);
  int overviewLevelFor(double x0, double y0, double sx, double sy, int w, int h) const;
  GDALDatasetH levelDataset(int level);
};

TerrainImagery::TerrainImagery(const std::string& path, const std::string& terrainCrsWkt)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.path = path;
  s.source = openRaster(path);
  GDALDatasetH ds = s.dataset();
  s.cols = GDALGetRasterXSize(ds);
  s.rows = GDALGetRasterYSize(ds);
  const int bands = GDALGetRasterCount(ds);
  if (bands > 4)
    throw InputError(path + ": " + std::to_string(bands) +
                     " bands; imagery needs 1 (grey), 2 (grey and alpha), 3 (RGB) or 4 (RGBA)");
  s.colourBands = bands >= 3 ? 3 : 1;
  s.alphaBand = bands == 2 || bands == 4 ? bands : 0;
  for (int b = 1; b <= bands; ++b) {
    checkBand(ds, b, path);
    GDALRasterBandH band = GDALGetRasterBand(ds, b);
    const GDALDataType type = GDALGetRasterDataType(band);
    if (GDALDataTypeIsComplex(type))
      throw InputError(path + ": band " + std::to_string(b) + " holds complex samples (" + GDALGetDataTypeName(type) +
                       "); imagery needs real colour values");
    if (GDALGetRasterColorInterpretation(band) == GCI_PaletteIndex || GDALGetRasterColorTable(band))
      throw InputError(path + ": band " + std::to_string(b) +
                       " is paletted (a colour table); expand it to colours first (gdal_translate -expand rgb)");
  }

  const RasterFrame frame = rasterFrame(ds);
  if (!frame.georeferenced)
    throw InputError(path + ": no geotransform; imagery must be georeferenced to lie on the terrain");
  if (frame.rotated)
    throw InputError(path + ": rotated or sheared geotransform; imagery needs a north-up grid (gdalwarp warps it "
                            "north-up)");
  std::copy(frame.geoTransform, frame.geoTransform + 6, s.gt);
  {
    const double x1 = s.gt[0] + s.cols * s.gt[1], y1 = s.gt[3] + s.rows * s.gt[5];
    const bool usable = std::isfinite(s.gt[0]) && std::isfinite(s.gt[3]) && std::isfinite(x1) && std::isfinite(y1) &&
                        std::isfinite(1.0 / s.gt[1]) && std::isfinite(1.0 / s.gt[5]);
    if (!usable) {
      char what[160];
      std::snprintf(what, sizeof what, "pixel size %g x %g at corner (%g, %g)", s.gt[1], s.gt[5], s.gt[0], s.gt[3]);
      throw InputError(path + ": unusable geotransform: " + what + " (non-finite, zero or too small to divide by)");
    }
  }

  // Sample values: 8-bit as they are, other types scaled from the colour bands' common range.
  for (int b = 1; b <= s.colourBands; ++b)
    s.byteColour = s.byteColour && GDALGetRasterDataType(GDALGetRasterBand(ds, b)) == GDT_Byte;
  const bool approxRange = std::uint64_t(s.cols) * std::uint64_t(s.rows) > kExactMinMaxPixels;
  auto bandRange = [&](int b, double range[2]) {
    CPLErrorReset();
    if (GDALComputeRasterMinMax(GDALGetRasterBand(ds, b), approxRange ? TRUE : FALSE, range) != CE_None)
      throw InputError(path + ": cannot compute the value range of band " + std::to_string(b) +
                       " (every sample nodata, or a truncated file?): " + lastGdalError());
  };
  if (!s.byteColour) {
    s.colourLo = std::numeric_limits<double>::infinity();
    s.colourHi = -std::numeric_limits<double>::infinity();
    for (int b = 1; b <= s.colourBands; ++b) {
      double range[2] = {0, 0};
      bandRange(b, range);
      s.colourLo = std::min(s.colourLo, range[0]);
      s.colourHi = std::max(s.colourHi, range[1]);
    }
  }
  if (s.alphaBand) {
    s.byteAlpha = GDALGetRasterDataType(GDALGetRasterBand(ds, s.alphaBand)) == GDT_Byte;
    if (!s.byteAlpha) {
      double range[2] = {0, 0};
      bandRange(s.alphaBand, range);
      s.alphaMax = range[1] > 0 ? range[1] : 1.0;
    }
  }

  // Frames.
  const std::string imageryWkt = crsWkt(ds);
  s.terrainWkt = terrainCrsWkt;
  const Srs terrainSrs(parseCrs(terrainCrsWkt, path + ": the terrain's CRS is not one GDAL can read, so the imagery "
                                                      "cannot be placed on it"));
  const Srs imagerySrs(parseCrs(imageryWkt, path + ": its CRS is not one GDAL can read"));
  if (!imagerySrs) {
    s.warnings.push_back(path + ": no CRS; taken to be in the terrain's CRS (" + crsName(terrainCrsWkt) + ")");
  } else if (!terrainSrs) {
    s.warnings.push_back(path + ": the terrain has no CRS; the imagery (" + crsName(imageryWkt) +
                         ") is taken to be in the terrain's frame as it is");
  } else {
    s.reproject = !OSRIsSame(imagerySrs.get(), terrainSrs.get());
  }

  if (!s.reproject) {
    const double xa = s.gt[0], xb = s.gt[0] + s.cols * s.gt[1];
    const double ya = s.gt[3], yb = s.gt[3] + s.rows * s.gt[5];
    s.extent = {std::min(xa, xb), std::min(ya, yb), std::max(xa, xb), std::max(ya, yb)};
    s.pixelSize = std::min(std::abs(s.gt[1]), std::abs(s.gt[5]));
    return;
  }
  // Reprojected: the transformation must be one GDAL can set up, and the imagery's outline must map
  // into the terrain's CRS.
  const std::string why = path + ": GDAL cannot transform it from its CRS (" + crsName(imageryWkt) +
                          ") to the terrain's (" + crsName(terrainCrsWkt) + ")";
  const std::string dstSrs = "DST_SRS=" + terrainCrsWkt;
  const char* options[] = {dstSrs.c_str(), nullptr};
  CPLErrorReset();
  s.toImagery.reset(GDALCreateGenImgProjTransformer2(ds, nullptr, const_cast<char**>(options)));
  if (!s.toImagery) throw InputError(why + ": " + lastGdalError());
  double outGt[6];
  int outCols = 0, outRows = 0;
  double outExtent[4];
  CPLErrorReset();
  if (GDALSuggestedWarpOutput2(ds, GDALGenImgProjTransform, s.toImagery.get(), outGt, &outCols, &outRows, outExtent,
                               0) != CE_None ||
      !(outCols > 0 && outRows > 0) || !std::isfinite(outGt[1]))
    throw InputError(why + " (its outline does not map into the terrain's CRS): " + lastGdalError());
  s.extent = {outExtent[0], outExtent[1], outExtent[2], outExtent[3]};
  s.pixelSize = std::abs(outGt[1]);
}

TerrainImagery::~TerrainImagery() = default;
TerrainImagery::TerrainImagery(TerrainImagery&&) noexcept = default;
TerrainImagery& TerrainImagery::operator=(TerrainImagery&&) noexcept = default;

const std::string& TerrainImagery::path() const { return state_->path; }
const std::vector<std::string>& TerrainImagery::warnings() const { return state_->warnings; }
bool TerrainImagery::reprojected() const { return state_->reproject; }
int TerrainImagery::colourBands() const { return state_->colourBands; }
bool TerrainImagery::hasAlpha() const { return state_->alphaBand != 0; }
ImageryExtent TerrainImagery::extent() const { return state_->extent; }
double TerrainImagery::pixelSize() const { return state_->pixelSize; }

std::vector<std::uint8_t> TerrainImagery::read(double x0, double y0, double spacingX, double spacingY, int width,
                                               int height) {
  if (width < 1 || height < 1 || std::int64_t(width) * std::int64_t(height) > kMaxImageryReadPixels)
    throw std::invalid_argument("TerrainImagery::read: " + std::to_string(width) + " x " + std::to_string(height) +
                                " pixels (1 to " + std::to_string(kMaxImageryReadPixels) + " allowed)");
  const double x1 = x0 + (width - 1) * spacingX, y1 = y0 - (height - 1) * spacingY;
  if (!(std::isfinite(x0) && std::isfinite(y0) && std::isfinite(x1) && std::isfinite(y1)))
    throw std::invalid_argument("TerrainImagery::read: non-finite coordinates");
  if (!(spacingX > 0 && spacingY > 0 && std::isfinite(spacingX) && std::isfinite(spacingY)))
    throw std::invalid_argument("TerrainImagery::read: the spacing must be positive and finite");
  std::vector<std::uint8_t> out(std::size_t(width) * std::size_t(height) * 4u, 0);
  const ImageryExtent& e = state_->extent;
  if (x1 < e.minX || x0 > e.maxX || y0 < e.minY || y1 > e.maxY) return out;  // nothing of it there
  if (state_->reproject) state_->readReprojected(x0, y0, spacingX, spacingY, width, height, out);
  else state_->readSameFrame(x0, y0, spacingX, spacingY, width, height, out);
  return out;
}

void TerrainImagery::State::readSameFrame(double x0, double y0, double sx, double sy, int w, int h,
                                          std::vector<std::uint8_t>& out) {
  GDALDatasetH ds = dataset();
  // Source pixel coordinates of output (i, j): column (x0 + i sx - gt0) / gt1, row (y0 - j sy - gt3) / gt5.
  const std::vector<AxisRead> xs = planAxis((x0 - gt[0]) / gt[1], sx / gt[1], w, cols);
  const std::vector<AxisRead> ys = planAxis((y0 - gt[3]) / gt[5], -sy / gt[5], h, rows);
  GDALRasterBandH band1 = GDALGetRasterBand(ds, 1);
  GDALRasterBandH alpha = alphaBand ? GDALGetRasterBand(ds, alphaBand)
                                    : ((GDALGetMaskFlags(band1) & GMF_ALL_VALID) ? nullptr : GDALGetMaskBand(band1));
  const bool alphaIsMask = !alphaBand;  // a mask band is 0 or 255, like an 8-bit alpha
  std::vector<float> colour[3], coverage;
  for (const AxisRead& ry : ys) {
    for (const AxisRead& rx : xs) {
      const std::size_t n = std::size_t(rx.count) * std::size_t(ry.count);
      GDALRasterIOExtraArg arg;
      INIT_RASTERIO_EXTRA_ARG(arg);
      arg.eResampleAlg = GRIORA_Bilinear;
      arg.bFloatingPointWindowValidity = TRUE;
      arg.dfXOff = rx.winOff;
      arg.dfYOff = ry.winOff;
      arg.dfXSize = rx.winSize;
      arg.dfYSize = ry.winSize;
      auto readBand = [&](GDALRasterBandH b, std::vector<float>& buffer) {
        buffer.resize(n);
        CPLErrorReset();
        if (GDALRasterIOEx(b, GF_Read, rx.intOff, ry.intOff, rx.intSize, ry.intSize, buffer.data(), rx.count, ry.count,
                           GDT_Float32, 0, 0, &arg) != CE_None)
          throw InputError(path + ": cannot read the imagery (truncated or corrupt file?): " + lastGdalError());
      };
      for (int b = 0; b < colourBands; ++b) readBand(GDALGetRasterBand(ds, b + 1), colour[b]);
      if (alpha) readBand(alpha, coverage);
      for (int m = 0; m < ry.count; ++m) {
        const int j = ry.out0 + m * ry.outStep;
        for (int k = 0; k < rx.count; ++k) {
          const int i = rx.out0 + k * rx.outStep;
          const std::size_t at = std::size_t(m) * std::size_t(rx.count) + std::size_t(k);
          const double a = alpha ? (alphaIsMask ? byteFrom(coverage[at]) : alphaByte(coverage[at])) : 255.0;
          double c[3];
          for (int b = 0; b < 3; ++b) c[b] = colourByte(colour[colourBands == 3 ? b : 0][at]);
          if (!(a > 0) || std::isnan(c[0]) || std::isnan(c[1]) || std::isnan(c[2])) continue;  // stays 0, 0, 0, 0
          std::uint8_t* p = out.data() + (std::size_t(j) * std::size_t(w) + std::size_t(i)) * 4u;
          p[0] = std::uint8_t(c[0]);
          p[1] = std::uint8_t(c[1]);
          p[2] = std::uint8_t(c[2]);
          p[3] = std::uint8_t(a);
        }
      }
    }
  }
}

int TerrainImagery::State::overviewLevelFor(double x0, double y0, double sx, double sy, int w, int h) const {
  GDALRasterBandH band1 = GDALGetRasterBand(dataset(), 1);
  const int count = GDALGetOverviewCount(band1);
  if (count == 0) return -1;
  // The read's spacing in full-resolution imagery pixels, at its centre.
  const double cx = x0 + 0.5 * (w - 1) * sx, cy = y0 - 0.5 * (h - 1) * sy;
  double px[3] = {cx, cx + sx, cx}, py[3] = {cy, cy, cy - sy}, pz[3] = {0, 0, 0};
  int ok[3] = {0, 0, 0};
  if (!GDALGenImgProjTransform(toImagery.get(), TRUE, 3, px, py, pz, ok) || !ok[0] || !ok[1] || !ok[2]) return -1;
  const double factor = std::min(std::hypot(px[1] - px[0], py[1] - py[0]), std::hypot(px[2] - px[0], py[2] - py[0]));
  int best = -1;
  double bestFactor = 1.0;
  for (int k = 0; k < count; ++k) {
    GDALRasterBandH ovr = GDALGetOverview(band1, k);
    if (!ovr || GDALGetRasterBandXSize(ovr) < 1) continue;
    const double f = double(cols) / GDALGetRasterBandXSize(ovr);
    if (f <= factor + kOverviewFactorSlack && f > bestFactor) best = k, bestFactor = f;
  }
  return best;
}

GDALDatasetH TerrainImagery::State::levelDataset(int level) {
  if (level < 0) return dataset();
  auto it = overviews.find(level);
  if (it == overviews.end()) {
    const std::string option = "OVERVIEW_LEVEL=" + std::to_string(level);
    const char* openOptions[] = {option.c_str(), nullptr};
    GDALDatasetH ovr = GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, openOptions, nullptr);
    it = overviews.emplace(level, GdalDataset(ovr)).first;
  }
  return it->second ? static_cast<GDALDatasetH>(it->second.get()) : dataset();
}

void TerrainImagery::State::readReprojected(double x0, double y0, double sx, double sy, int w, int h,
                                            std::vector<std::uint8_t>& out) {
  GDALDatasetH src = levelDataset(overviewLevelFor(x0, y0, sx, sy, w, h));
  const bool byteOut = byteColour && byteAlpha;
  const GDALDataType type = byteOut ? GDT_Byte : GDT_Float32;
  const int dstAlpha = colourBands + 1;
  GdalDataset dstOwned(GDALCreate(GDALGetDriverByName("MEM"), "", w, h, dstAlpha, type, nullptr));
  auto* dst = static_cast<GDALDatasetH>(dstOwned.get());
  if (!dst) throw std::runtime_error("TerrainImagery: GDAL's MEM driver cannot hold " + std::to_string(w) + " x " +
                                     std::to_string(h) + " pixels");
  // Pixel (i, j) is centred on map (x0 + i sx, y0 - j sy).
  double dstGt[6] = {x0 - 0.5 * sx, sx, 0, y0 + 0.5 * sy, 0, -sy};
  GDALSetGeoTransform(dst, dstGt);
  GDALSetProjection(dst, terrainWkt.c_str());

  CPLErrorReset();
  void* exact = GDALCreateGenImgProjTransformer2(src, dst, nullptr);
  if (!exact) throw InputError(path + ": GDAL cannot transform it to the terrain's CRS: " + lastGdalError());
  Transformer transformer(GDALCreateApproxTransformer(GDALGenImgProjTransform, exact, kWarpErrorThresholdPixels));
  GDALApproxTransformerOwnsSubtransformer(transformer.get(), TRUE);

  std::unique_ptr<GDALWarpOptions, WarpOptionsClose> wo(GDALCreateWarpOptions());
  wo->hSrcDS = src;
  wo->hDstDS = dst;
  wo->eResampleAlg = GRA_Bilinear;
  wo->eWorkingDataType = type;
  wo->nBandCount = colourBands;
  wo->panSrcBands = static_cast<int*>(CPLMalloc(sizeof(int) * std::size_t(colourBands)));
  wo->panDstBands = static_cast<int*>(CPLMalloc(sizeof(int) * std::size_t(colourBands)));
  for (int b = 0; b < colourBands; ++b) wo->panSrcBands[b] = wo->panDstBands[b] = b + 1;
  wo->nSrcAlphaBand = alphaBand;
  wo->nDstAlphaBand = dstAlpha;
  wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "INIT_DEST", "0");
  wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "DST_ALPHA_MAX", "255");
  if (alphaBand && !byteAlpha)
    wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "SRC_ALPHA_MAX", CPLSPrintf("%.17g", alphaMax));
  if (!alphaBand) {
    const BandNoData first = bandNoData(GDALGetRasterBand(src, 1));
    if (first.has) {
      wo->padfSrcNoDataReal = static_cast<double*>(CPLMalloc(sizeof(double) * std::size_t(colourBands)));
      for (int b = 0; b < colourBands; ++b) {
        const BandNoData nd = bandNoData(GDALGetRasterBand(src, b + 1));
        wo->padfSrcNoDataReal[b] = nd.has ? nd.value : first.value;
      }
      wo->papszWarpOptions = CSLSetNameValue(wo->papszWarpOptions, "UNIFIED_SRC_NODATA", "YES");
    }
  }
  wo->pfnTransformer = GDALApproxTransform;
  wo->pTransformerArg = transformer.get();

  CPLErrorReset();
  std::unique_ptr<void, WarpOperationClose> operation(GDALCreateWarpOperation(wo.get()));
  if (!operation || GDALChunkAndWarpImage(static_cast<GDALWarpOperationH>(operation.get()), 0, 0, w, h) != CE_None)
    throw InputError(path + ": cannot warp the imagery to the terrain's CRS (truncated or corrupt file?): " +
                     lastGdalError());
  operation.reset();

  const std::size_t n = std::size_t(w) * std::size_t(h);
  std::vector<float> colour[3], coverage(n);
  auto readBand = [&](int b, std::vector<float>& buffer) {
    buffer.resize(n);
    if (GDALRasterIO(GDALGetRasterBand(dst, b), GF_Read, 0, 0, w, h, buffer.data(), w, h, GDT_Float32, 0, 0) != CE_None)
      throw std::runtime_error("TerrainImagery: cannot read back GDAL's MEM dataset: " + lastGdalError());
  };
  for (int b = 0; b < colourBands; ++b) readBand(b + 1, colour[b]);
  readBand(dstAlpha, coverage);
  for (std::size_t at = 0; at < n; ++at) {
    const double a = byteFrom(coverage[at]);  // the warper's alpha is 0..255 (DST_ALPHA_MAX)
    double c[3];
    for (int b = 0; b < 3; ++b) c[b] = colourByte(colour[colourBands == 3 ? b : 0][at]);
    if (!(a > 0) || std::isnan(c[0]) || std::isnan(c[1]) || std::isnan(c[2])) continue;
    std::uint8_t* p = out.data() + at * 4u;
    p[0] = std::uint8_t(c[0]);
    p[1] = std::uint8_t(c[1]);
    p[2] = std::uint8_t(c[2]);
    p[3] = std::uint8_t(a);
  }
}

void requireImageryOverlap(const TerrainImagery& imagery, double x0, double y0, double x1, double y1) {
  const ImageryExtent e = imagery.extent();
  if (e.maxX <= std::min(x0, x1) || e.minX >= std::max(x0, x1) || e.maxY <= std::min(y0, y1) || e.minY >= std::max(y0, y1)) {
    char text[256];
    std::snprintf(text, sizeof text, ": does not overlap the terrain (imagery x %.3f..%.3f, y %.3f..%.3f; terrain x %.3f..%.3f, y %.3f..%.3f)",
                  e.minX, e.maxX, e.minY, e.maxY, std::min(x0, x1), std::max(x0, x1), std::min(y0, y1), std::max(y0, y1));
    throw InputError(imagery.path() + text);
  }
}

void writeImageryCog(const std::string& out, int cols, int rows, const std::vector<std::uint8_t>& rgb, double originX,
                     double originY, double dx, double dy, const std::string& crs, bool overwrite) {
  if (cols < 1 || rows < 1 || rgb.size() != std::size_t(cols) * std::size_t(rows) * 3u)
    throw std::invalid_argument("writeImageryCog: rgb does not hold cols x rows RGB pixels");
  writeImageryCog(
      out, cols, rows,
      [&](int r0, int count, std::uint8_t* stripe) {
        std::copy_n(rgb.begin() + std::ptrdiff_t(r0) * cols * 3, std::size_t(count) * std::size_t(cols) * 3u, stripe);
      },
      originX, originY, dx, dy, crs, overwrite, ImageryCompression::Deflate);
}

void writeImageryCog(const std::string& out, int cols, int rows, const ImageryRowSource& source, double originX,
                     double originY, double dx, double dy, const std::string& crs, bool overwrite,
                     ImageryCompression compression) {
  initGdal();
  if (cols < 1 || rows < 1) throw std::invalid_argument("writeImageryCog: no pixels");
  std::error_code ec;
  if (fs::exists(out, ec)) {
    if (fs::is_directory(out, ec)) throw InputError(out + ": is a folder; the imagery needs a file name");
    if (!overwrite) throw InputError(out + ": already exists (use --overwrite to replace it)");
  }
  const fs::path parent = fs::path(out).has_parent_path() ? fs::path(out).parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) throw InputError(out + ": the folder " + parent.string() + " does not exist");

  // The pixels stripe by stripe into a tiled scratch GeoTIFF beside the output (never held whole),
  // which GDAL's COG driver then copies with its overviews.
  OutputFile stripes(out, ".tif", "stripes");
  const char* scratchOptions[] = {"TILED=YES", "BLOCKXSIZE=512", "BLOCKYSIZE=512", "INTERLEAVE=PIXEL", "BIGTIFF=IF_NEEDED",
                                  nullptr};
  GdalDataset scratchOwned(GDALCreate(GDALGetDriverByName("GTiff"), stripes.tempPath().c_str(), cols, rows, 3, GDT_Byte,
                                      const_cast<char**>(scratchOptions)));
  auto* scratch = static_cast<GDALDatasetH>(scratchOwned.get());
  if (!scratch) throw InputError(out + ": cannot write the imagery file: " + lastGdalError());
  double gt[6] = {originX - 0.5 * dx, dx, 0, originY + 0.5 * dy, 0, -dy};
  GDALSetGeoTransform(scratch, gt);
  if (!crs.empty()) {
    const Srs srs(parseCrs(crs, crs + ": not a CRS GDAL knows"));
    char* wkt = nullptr;
    OSRExportToWkt(srs.get(), &wkt);
    GDALSetProjection(scratch, wkt);
    CPLFree(wkt);
  }
  const GDALColorInterp interp[3] = {GCI_RedBand, GCI_GreenBand, GCI_BlueBand};
  for (int b = 0; b < 3; ++b) GDALSetRasterColorInterpretation(GDALGetRasterBand(scratch, b + 1), interp[b]);
  std::vector<std::uint8_t> stripe(std::size_t(kImageryStripeRows) * std::size_t(cols) * 3u);
  for (int r0 = 0; r0 < rows; r0 += kImageryStripeRows) {
    const int count = std::min(kImageryStripeRows, rows - r0);
    source(r0, count, stripe.data());
    // Interleaved RGB: 3 bytes a pixel, band b at byte b.
    int bands[3] = {1, 2, 3};
    if (GDALDatasetRasterIO(scratch, GF_Write, 0, r0, cols, count, stripe.data(), cols, count, GDT_Byte, 3, bands, 3,
                            3 * std::int64_t(cols), 1) != CE_None)
      throw InputError(out + ": cannot write the imagery file: " + lastGdalError());
  }
  GDALDriverH cog = GDALGetDriverByName("COG");
  if (!cog) throw std::runtime_error("GDAL has no COG driver");
  OutputFile tmp(out, ".tif");
  const bool jpeg = compression == ImageryCompression::Jpeg;
  const std::string quality = "QUALITY=" + std::to_string(kImageryJpegQuality);
  const char* options[] = {jpeg ? "COMPRESS=JPEG" : "COMPRESS=DEFLATE",
                           jpeg ? quality.c_str() : "PREDICTOR=YES",
                           "BLOCKSIZE=512",
                           "OVERVIEWS=AUTO",
                           "OVERVIEW_RESAMPLING=AVERAGE",
                           "BIGTIFF=IF_SAFER",
                           nullptr};
  CPLErrorReset();
  GDALDatasetH written = GDALCreateCopy(cog, tmp.tempPath().c_str(), scratch, FALSE, const_cast<char**>(options),
                                        nullptr, nullptr);
  if (!written) throw InputError(out + ": cannot write the imagery file: " + lastGdalError());
  CPLErrorReset();
  GDALClose(written);
  if (CPLGetLastErrorType() == CE_Failure) throw InputError(out + ": cannot write the imagery file: " + lastGdalError());
  tmp.commit();
}

}  // namespace nestwalk::terrain
