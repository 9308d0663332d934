// The synthetic orthophoto of a generated mining dump (terrain/mining_dump.h): what `nestwalk
// make-scene` writes as ortho.tif beside the DEM (and `make-terrain --ortho FILE`), the bundled
// scene's draped imagery.
//
// Grid: the DEM's own: pixel (c, r) is centred on DEM sample (c, r), so the image has the DEM's
// CRS, extent and resolution (1 m for the bundled dump), RGB 8-bit, row 0 north; or, for a drone's
// finer orthophoto (writeFineMiningDumpOrtho), pixels of any size over the same area.
// Colour: the material of the surface the generator built at the sample (MiningDump::surfaces;
// the rule is in mining_dump.h), from kDumpSurfaceColours, times a smooth brightness patchiness
// (value noise on a lattice of kOrthoPatchWavelength metres, within +-kOrthoPatchAmplitude), plus a
// per-pixel grain (Gaussian, kOrthoGrainLevels levels standard deviation, each channel on its own),
// rounded and clamped to 0..255. No shading is baked in: the renderer lights the terrain itself.
// Deterministic: the noise comes from core/random.h's SplitMix64 seeded with the given seed (salted
// apart from the terrain's own draws), so the same dump and seed give the same bytes.
// Thread safety: pure functions; writeMiningDumpOrtho writes one file (core/output_file.h rules).
#pragma once

#include "nestwalk/terrain/mining_dump.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace nestwalk::terrain {

/// sRGB 8-bit base colour of each DumpSurface, in the enum's order: ground green-brown, the ditch
/// dark and wet, pits dark grey-brown, faces a darker ochre, berms the grey of compacted haul
/// lanes, the top a light grey-brown, the ramp's running surface gravel grey, its cut and fill
/// slopes a greyer brown than the faces. Every two are at least 31 levels apart (Euclidean RGB); a
/// colour scaled by the patchiness's extremes (1 +- kOrthoPatchAmplitude) stays at least 13 levels
/// nearer its own base colour than any other, so the nearest base colour of a pixel (its grain
/// averaged over a few pixels) tells its material.
inline constexpr std::array<std::array<std::uint8_t, 3>, kDumpSurfaceCount> kDumpSurfaceColours{{
    {104, 116, 66},   // Ground
    {66, 62, 52},     // Ditch
    {84, 80, 70},     // Pit
    {146, 112, 70},   // Face
    {150, 148, 140},  // Berm
    {196, 182, 152},  // Top
    {122, 122, 118},  // Ramp
    {118, 94, 86},    // RampSide
}};

/// Metres: the spacing of the brightness patchiness's lattice (patches of a few metres to tens of
/// metres, like uneven wetness and fines on a real dump).
inline constexpr double kOrthoPatchWavelength = 16.0;
/// Dimensionless: the patchiness scales the base colour by 1 +- this at most.
inline constexpr double kOrthoPatchAmplitude = 0.06;
/// 8-bit levels: the standard deviation of the per-pixel grain.
inline constexpr double kOrthoGrainLevels = 3.0;

/// Metres: an orthophoto of pixels finer than this shows the ground's own texture (below).
inline constexpr double kOrthoTextureBelowPixelM = 0.5;
/// The texture of a fine orthophoto (metres and factors of the base colour): gravel mottling on
/// two scales, stones (a tenth of the surface lighter or darker) on every surface but the ground and
/// the ditch, and vegetation patches (reclamation) on the ground and the top.
inline constexpr double kOrthoGravelWavelengthM = 0.6, kOrthoGravelAmplitude = 0.08;
inline constexpr double kOrthoGritWavelengthM = 0.25, kOrthoGritAmplitude = 0.05;
inline constexpr double kOrthoStoneWavelengthM = 0.35, kOrthoStoneThreshold = 0.6;
inline constexpr double kOrthoVegetationWavelengthM = 5.0, kOrthoVegetationThreshold = 0.3;
inline constexpr std::array<std::uint8_t, 3> kOrthoVegetationColour{72, 104, 48};

/// The haul trucks' tyre tracks on the ramp's running surface (MiningDumpLayout's ramp) of a fine
/// orthophoto: two lanes kOrthoLaneOffsetM either side of the ramp's axis, each with two wheel paths
/// kOrthoWheelGaugeM apart (centre to centre), kOrthoTrackWidthM wide (dual tyres), each path
/// wandering by up to kOrthoTrackWanderM over kOrthoTrackWanderWavelengthM along the ramp and fading
/// into the gravel beside it over kOrthoTrackEdgeM. In a track the surface is compacted: its colour
/// times kOrthoTrackDarkening, tread lugs across it every kOrthoTreadPitchM (+- kOrthoTreadAmplitude;
/// at pixels up to kOrthoTreadBelowPixelM), no stones. Metres and factors of the colour; a 40-tonne truck's dual tyres and lane.
inline constexpr double kOrthoLaneOffsetM = 5.0, kOrthoWheelGaugeM = 4.8, kOrthoTrackWidthM = 1.4;
inline constexpr double kOrthoTrackWanderM = 0.3, kOrthoTrackWanderWavelengthM = 25.0, kOrthoTrackEdgeM = 0.2;
inline constexpr double kOrthoTrackDarkening = 0.8, kOrthoTreadPitchM = 0.4, kOrthoTreadAmplitude = 0.06;
/// Metres: the tread is drawn only at pixels this fine (4 a lug period); coarser pixels, sampling
/// it at their centres, would show a beat pattern instead of the lugs.
inline constexpr double kOrthoTreadBelowPixelM = kOrthoTreadPitchM / 4;

/// The orthophoto's pixels: dump.cols x dump.rows, row-major from the north row, RGB interleaved.
std::vector<std::uint8_t> miningDumpOrtho(const MiningDump& dump, std::uint64_t seed);

/// Writes miningDumpOrtho(dump, seed) to `out` as the engine's imagery file (writeImageryCog,
/// terrain_imagery.h: a COG with overviews, written to a temporary name and renamed) on the DEM's
/// grid in `crs`. InputError naming the file when it cannot be written, or exists and not
/// `overwrite`.
void writeMiningDumpOrtho(const std::string& out, const MiningDump& dump, std::uint64_t seed, const std::string& crs,
                          bool overwrite);

/// A drone's orthophoto of the dump `params` makes: pixels of `pixel` metres over its whole area
/// (finer than its DEM: pixel centres on a grid of the area's own edges), each the material the
/// generator finds at the pixel's centre (the same dump at that spacing), coloured as above and,
/// below kOrthoTextureBelowPixelM, with the ground's texture and the ramp's tyre tracks; written as a JPEG COG with overviews
/// (writeImageryCog's streamed form: memory is a stripe of rows), in `crs`. Deterministic for a seed
/// and pixel. std::invalid_argument for a pixel the generator refuses (more than 65,536 a side);
/// InputError naming the file when it cannot be written, or exists and not `overwrite`.
void writeFineMiningDumpOrtho(const std::string& out, const MiningDumpParams& params, double pixel,
                              const std::string& crs, bool overwrite);

}  // namespace nestwalk::terrain
