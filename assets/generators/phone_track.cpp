#include "assets/generators/phone_track.h"

#include "assets/generators/to_lon_lat.h"

#include <cpl_conv.h>
#include <cpl_string.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>

namespace nestwalk::assets {
namespace {

/// A standard normal number (Box-Muller on the generator's bits: the same on every standard library).
double normal(std::mt19937_64& rng) {
  const double u1 = (double(rng() >> 11) + 1.0) * 0x1.0p-53, u2 = double(rng() >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

std::string isoTime(std::int64_t unixTime) {
  const std::time_t t = std::time_t(unixTime);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[64];  // room for any int the compiler sees (the year is 4 digits here)
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02dZ", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                tm.tm_hour, tm.tm_min, tm.tm_sec);
  return buf;
}

/// Text as XML character data (GDAL's escaping).
std::string xmlText(const std::string& text) {
  char* escaped = CPLEscapeString(text.c_str(), -1, CPLES_XML);
  std::string out = escaped;
  CPLFree(escaped);
  return out;
}

std::string latLon(const Eigen::Vector2d& lonLat) {
  char buf[80];
  std::snprintf(buf, sizeof buf, "lat=\"%.8f\" lon=\"%.8f\"", lonLat.y(), lonLat.x());
  return buf;
}

}  // namespace

std::string phoneTrackGpx(const PhoneTrack& track, const terrain::Heightfield& ground, const char* crs,
                          std::uint64_t seed) {
  if (track.legs.size() < 2) throw std::runtime_error(track.name + ": a track needs two points");
  const ToLonLat toLonLat(crs);
  std::mt19937_64 rng(seed);
  std::string gpx = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                    "<gpx version=\"1.1\" creator=\"nestwalk make-scene\" xmlns=\"http://www.topografix.com/GPX/1/1\">\n";
  for (const auto& [name, p] : track.waypoints) gpx += "<wpt " + latLon(toLonLat(p)) + "><name>" + xmlText(name) + "</name></wpt>\n";
  gpx += "<trk><name>" + xmlText(track.name) + "</name><trkseg>\n";
  // The walk as a function of time: legs at the speed, the pause on reaching legs[pauseAt].
  std::int64_t second = 0;
  auto fix = [&](const Eigen::Vector2d& at) {
    const Eigen::Vector2d p = at + track.noiseSigma * Eigen::Vector2d(normal(rng), normal(rng));
    const std::optional<double> z = ground.groundHeight(p.x(), p.y());
    if (!z) throw std::runtime_error(track.name + ": a fix has no ground under it");
    char ele[32];
    std::snprintf(ele, sizeof ele, "%.1f", std::round(*z * 10.0) / 10.0);
    gpx += "<trkpt " + latLon(toLonLat(p)) + "><ele>" + ele + "</ele><time>" + isoTime(track.startUnixTime + second) +
           "</time></trkpt>\n";
    ++second;
  };
  double carried = 0;  // metres already walked into the current leg at the next fix
  for (std::size_t k = 0; k + 1 < track.legs.size(); ++k) {
    const Eigen::Vector2d a = track.legs[k], d = track.legs[k + 1] - a;
    const double length = d.norm();
    for (double s = carried; s < length; s += track.speed) fix(a + (s / length) * d);
    carried = std::fmod(carried - length, track.speed);
    if (carried < 0) carried += track.speed;
    if (k + 1 == track.pauseAt)
      for (double t = 0; t < track.pauseSeconds; t += 1.0) fix(track.legs[k + 1]);
  }
  fix(track.legs.back());
  return gpx + "</trkseg></trk>\n</gpx>\n";
}

}  // namespace nestwalk::assets
