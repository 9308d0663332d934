// Which OBB fitter a scene uses (obb_fit.h has the fitters). Its own small header so that a scene
// file can name the choice without the fitting code.
// Thread safety: pure functions.
#pragma once

#include <optional>
#include <string>

namespace nestwalk {

enum class ObbFitter {
  Covariance,  // Gottschalk 1996
  HullSearch,  // the tighter fitter (see obb_fit.cpp for the method and its cost)
};

const char* fitterName(ObbFitter f);                      // "covariance", "hull-search"
std::optional<ObbFitter> parseFitter(const std::string& name);

}  // namespace nestwalk
