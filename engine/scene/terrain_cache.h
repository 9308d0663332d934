// The terrain cache: where a scene whose terrain is a plain DEM (any raster GDAL reads, without a
// pyramid of its own beside it) gets its terrain pyramid (terrain/terrain_pyramid_format.h). On
// first use the DEM is imported once (terrain/terrain_import.h, default options: the same grid and
// values) into an entry of the cache; later loads reuse the entry while the DEM is unchanged.
//
// An entry is a folder named after a hash of the DEM's canonical path, holding terrain.tif (the
// import), its terrain.pyramid.tif and `source`: the DEM's path and identity (size, modification
// time in nanoseconds, inode, device) when it was imported, and the grid the scene read (size,
// share of holes, height range). An entry is used only when all of them still match and its
// pyramid opens (its own checks: version, fingerprint, CRC-32s); otherwise it
// is imported again. Entries are written as a temporary folder renamed into place
// (core/output_file.h). The cache is best effort: when the folder cannot be written or the import
// fails, the scene is loaded without a pyramid (the renderer then computes its errors).
//
// Folder: NESTWALK_TERRAIN_CACHE names it ("off" disables the cache); else $XDG_CACHE_HOME/nestwalk/
// terrain, else $HOME/.cache/nestwalk/terrain. At most kMaxTerrainCacheEntries entries; storing one
// past that removes the least recently used (an entry's folder is touched when used). An entry
// costs about the DEM's size again (the COG and its pyramid).
//
// One thing the import changes: a valid sample equal to the terrain files' nodata value (-32768 m)
// becomes a hole there; the cached pyramid is then not used for that DEM (its grid errors would not
// be the DEM's), which cachedTerrainPyramid checks.
//
// Thread safety: as the model cache (model_cache.h): entries are whole folders renamed into place;
// two processes importing the same DEM at once each write their own temporary folder, the last
// rename wins with the same content. Two threads of one process share the temporary folder's name
// (core/output_file.h) and may spoil each other's import: the scene then loads without a pyramid.
// Temporary folders left by a killed import are removed after a day. The folder is looked up in
// the environment on every call.
#pragma once

#include <functional>
#include <memory>
#include <string>

namespace nestwalk {
namespace terrain {
class TerrainPyramid;
class Heightfield;
}  // namespace terrain

/// Entries kept at most (see above).
inline constexpr int kMaxTerrainCacheEntries = 16;

/// The cache's folder, or empty when it is off.
std::string terrainCacheFolder();

/// The pyramid of the DEM at `demPath` from the cache, importing it first when no entry matches
/// (`note` is told, once, before the import starts). `hf` is the DEM as the scene read it: the
/// entry's grid must be its (same size, same holes). Null (a DEM too large to read whole, to be
/// paged from the entry): the entry is keyed by the DEM's identity and its band's header (size,
/// data type, nodata value, geotransform: an .aux.xml's nodata changes it, a VRT's sources do
/// not), and a valid sample at the terrain files' nodata value (-32768, which the import makes a
/// hole) is not looked for: such a DEM pages with holes there. The two keys differ, so a DEM read
/// both ways has two entries. Null when the cache is off, cannot be written, the import fails or
/// the grids differ.
std::shared_ptr<const terrain::TerrainPyramid> cachedTerrainPyramid(const std::string& demPath,
                                                                    const terrain::Heightfield* hf,
                                                                    const std::function<void(const std::string&)>& note);

/// The imagery to drape for a scene whose "imagery" is `imageryPath` over a terrain in
/// `terrainCrsWkt`: the file itself when it is ready to drape as it is (terrain::imageryReadyToDrape:
/// in the terrain's CRS, small, or tiled with overviews); else its import (terrain/imagery_import.h:
/// a JPEG COG with overviews in the terrain's CRS) from an entry of this cache, imported on first
/// use (`note` is told before) and reused while the file and the terrain's CRS are unchanged. An
/// entry is a folder "imagery-" + a hash of the canonical path, holding imagery.tif and `source`
/// (the file's path and identity, and the CRS), stored and pruned as the terrain's entries are (one
/// count for both). Best effort: the file itself when the cache is off, cannot be written or the
/// import fails (opening it to draw then says what is wrong with it).
std::string cachedImagery(const std::string& imageryPath, const std::string& terrainCrsWkt,
                          const std::function<void(const std::string&)>& note);

}  // namespace nestwalk
