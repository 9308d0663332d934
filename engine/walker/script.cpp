// Flythrough script parser (format in script.h). Strict: every line is one command with exactly
// the arguments its form takes; anything else is an InputError "FILE:LINE: KEYWORD: problem".
// Numbers go through std::from_chars, so a script reads the same under any C/C++ locale.
#include "nestwalk/walker/script.h"

#include "nestwalk/core/input_error.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string_view>

namespace nestwalk {
namespace {

// Largest |pitch| a `look` takes, degrees: straight up or straight down. Beyond it the view
// would turn over (the heading would flip), which no walkthrough means.
constexpr double kMaxPitchDeg = 90.0;

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    std::size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) words.push_back(line.substr(i, j - i));
    i = j;
  }
  return words;
}

class LineParser {
 public:
  LineParser(const std::string& path, int line, std::vector<std::string_view> words)
      : path_(path), line_(line), words_(std::move(words)) {}

  [[noreturn]] void fail(const std::string& keyword, const std::string& problem) const {
    throw InputError(path_ + ":" + std::to_string(line_) + ": " + keyword + ": " + problem);
  }

  std::size_t size() const { return words_.size(); }
  std::string_view word(std::size_t i) const { return words_[i]; }

  /// Word i as a finite number; errors name the keyword and the word.
  double number(const std::string& keyword, std::size_t i) const {
    const std::string_view w = words_[i];
    double v = 0;
    // from_chars accepts no leading '+'; a script writer may well write one.
    const std::string_view digits = (w.size() > 1 && w[0] == '+' && w[1] != '-') ? w.substr(1) : w;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (ec == std::errc::result_out_of_range) fail(keyword, "'" + std::string(w) + "' is not a finite number");
    if (ec != std::errc() || end != digits.data() + digits.size())
      fail(keyword, "'" + std::string(w) + "' is not a number");
    if (!std::isfinite(v)) fail(keyword, "'" + std::string(w) + "' is not a finite number");
    return v;
  }

  double nonNegative(const std::string& keyword, std::size_t i, const char* what) const {
    const double v = number(keyword, i);
    if (v < 0) fail(keyword, std::string(what) + " must not be negative, got " + std::string(words_[i]));
    return v;
  }

  /// Checks that the words after the keyword are one of `counts` numbers; else "expected 2 or 3
  /// numbers, got 1".
  void expectCount(const std::string& keyword, std::initializer_list<std::size_t> counts) const {
    const std::size_t got = words_.size() - 1;
    if (std::find(counts.begin(), counts.end(), got) != counts.end()) return;
    std::string want;
    std::size_t k = 0;
    for (std::size_t c : counts) {
      if (k++) want += k == counts.size() ? " or " : ", ";
      want += std::to_string(c);
    }
    const bool one = counts.size() == 1 && *counts.begin() == 1;
    fail(keyword, "expected " + want + (one ? " number" : " numbers") + ", got " + std::to_string(got));
  }

 private:
  const std::string& path_;
  int line_;
  std::vector<std::string_view> words_;
};

bool isMotion(ScriptOp op) {
  switch (op) {
    case ScriptOp::Goto:
    case ScriptOp::Move:
    case ScriptOp::MoveBy:
    case ScriptOp::Turn:
    case ScriptOp::Heading:
    case ScriptOp::Look:
    case ScriptOp::Wait:
      return true;
    default:
      return false;
  }
}

std::string quoted(std::string_view w) { return "'" + std::string(w) + "'"; }

/// One `expect ...` line (words[0] == "expect").
ScriptCommand parseExpect(const LineParser& p) {
  ScriptCommand c;
  const std::string kw = "expect";
  if (p.size() < 2) p.fail(kw, "expected blocked, free, ground, position or clearance");
  const std::string_view what = p.word(1);
  if (what == "blocked") {
    c.op = ScriptOp::ExpectBlocked;
    if (p.size() == 2) return c;
    if (p.size() == 4 && p.word(2) == "by") {
      c.name = std::string(p.word(3));
      return c;
    }
    p.fail("expect blocked", "expected `expect blocked` or `expect blocked by NAME`");
  }
  if (what == "free") {
    c.op = ScriptOp::ExpectFree;
    if (p.size() != 2) p.fail("expect free", "takes no arguments, got " + std::to_string(p.size() - 2));
    return c;
  }
  if (what == "ground") {
    c.op = ScriptOp::ExpectGround;
    if (p.size() != 4 || p.word(2) != "within") p.fail("expect ground", "expected `expect ground within TOL`");
    c.tolerance = p.nonNegative("expect ground", 3, "the tolerance");
    return c;
  }
  if (what == "position") {
    c.op = ScriptOp::ExpectPosition;
    if (p.size() != 6 || p.word(4) != "within")
      p.fail("expect position", "expected `expect position X Y within TOL`");
    c.v = Eigen::Vector3d(p.number("expect position", 2), p.number("expect position", 3), 0);
    c.tolerance = p.nonNegative("expect position", 5, "the tolerance");
    return c;
  }
  if (what == "clearance") {
    c.op = ScriptOp::ExpectClearance;
    if (p.size() != 5 || p.word(2) != "at" || p.word(3) != "least")
      p.fail("expect clearance", "expected `expect clearance at least C`");
    c.tolerance = p.nonNegative("expect clearance", 4, "the clearance");
    return c;
  }
  p.fail(kw, "unknown expectation " + quoted(what) + " (expected blocked, free, ground, position or clearance)");
}

ScriptCommand parseLine(const LineParser& p) {
  const std::string kw(p.word(0));
  ScriptCommand c;
  if (kw == "expect") return parseExpect(p);
  if (kw == "mode") {
    c.op = ScriptOp::Mode;
    if (p.size() != 2) p.fail(kw, "expected `mode walk` or `mode fly`");
    if (p.word(1) == "fly") c.fly = true;
    else if (p.word(1) != "walk") p.fail(kw, "expected walk or fly, got " + quoted(p.word(1)));
    return c;
  }
  if (kw == "speed" || kw == "clearance" || kw == "turn" || kw == "heading" || kw == "look" || kw == "wait") {
    p.expectCount(kw, {1});
    if (kw == "speed") {
      c.op = ScriptOp::Speed;
      c.v.x() = p.number(kw, 1);
      if (!(c.v.x() > 0)) p.fail(kw, "the speed must be positive, got " + std::string(p.word(1)));
    } else if (kw == "clearance") {
      c.op = ScriptOp::Clearance;
      c.v.x() = p.nonNegative(kw, 1, "the clearance");
    } else if (kw == "turn") {
      c.op = ScriptOp::Turn;
      c.v.x() = p.number(kw, 1);
    } else if (kw == "heading") {
      c.op = ScriptOp::Heading;
      c.v.x() = p.number(kw, 1);
    } else if (kw == "look") {
      c.op = ScriptOp::Look;
      c.v.x() = p.number(kw, 1);
      if (std::abs(c.v.x()) > kMaxPitchDeg)
        p.fail(kw, "the pitch must be within [-90, 90] degrees, got " + std::string(p.word(1)));
    } else {
      c.op = ScriptOp::Wait;
      c.v.x() = p.nonNegative(kw, 1, "the time");
    }
    return c;
  }
  if (kw == "start") {
    c.op = ScriptOp::Start;
    std::size_t end = p.size();
    if (end >= 3 && p.word(end - 2) == "heading") {
      c.hasHeading = true;
      c.heading = p.number(kw, end - 1);
      end -= 2;
    }
    const std::size_t n = end - 1;
    if (n != 2 && n != 3)
      p.fail(kw, "expected 2 or 3 numbers (and optionally `heading H`), got " + std::to_string(n) +
                     (c.hasHeading ? " before `heading`" : ""));
    for (std::size_t i = 0; i < n; ++i) c.v[Eigen::Index(i)] = p.number(kw, 1 + i);
    c.hasZ = n == 3;
    return c;
  }
  if (kw == "goto") {
    c.op = ScriptOp::Goto;
    std::size_t end = p.size();
    if (end >= 3 && p.word(end - 2) == "by") {
      c.hasTime = true;
      c.time = p.nonNegative(kw, end - 1, "the arrival time");
      end -= 2;
    }
    const std::size_t n = end - 1;
    if (n != 2 && n != 3)
      p.fail(kw, "expected 2 or 3 numbers, got " + std::to_string(n) + (c.hasTime ? " before `by`" : ""));
    for (std::size_t i = 0; i < n; ++i) c.v[Eigen::Index(i)] = p.number(kw, 1 + i);
    c.hasZ = n == 3;
    return c;
  }
  if (kw == "move") {
    p.expectCount(kw, {1, 2, 3});
    if (p.size() == 2) {
      c.op = ScriptOp::Move;
      c.v.x() = p.number(kw, 1);
    } else {
      c.op = ScriptOp::MoveBy;
      for (std::size_t i = 1; i < p.size(); ++i) c.v[Eigen::Index(i - 1)] = p.number(kw, i);
      c.hasZ = p.size() == 4;
    }
    return c;
  }
  p.fail(kw, "unknown command (expected mode, speed, clearance, start, goto, move, turn, heading, look, wait or "
             "expect)");
}

}  // namespace

const char* scriptOpName(ScriptOp op) {
  switch (op) {
    case ScriptOp::Mode: return "mode";
    case ScriptOp::Speed: return "speed";
    case ScriptOp::Clearance: return "clearance";
    case ScriptOp::Start: return "start";
    case ScriptOp::Goto: return "goto";
    case ScriptOp::Move: return "move";
    case ScriptOp::MoveBy: return "move";
    case ScriptOp::Turn: return "turn";
    case ScriptOp::Heading: return "heading";
    case ScriptOp::Look: return "look";
    case ScriptOp::Wait: return "wait";
    case ScriptOp::ExpectBlocked: return "expect blocked";
    case ScriptOp::ExpectFree: return "expect free";
    case ScriptOp::ExpectGround: return "expect ground";
    case ScriptOp::ExpectPosition: return "expect position";
    case ScriptOp::ExpectClearance: return "expect clearance";
  }
  return "?";
}

Script parseScript(const std::string& text, const std::string& path) {
  Script script;
  script.path = path;
  bool started = false, moved = false;
  int lineNo = 0;
  // A UTF-8 byte order mark (some Windows editors write one) is not part of the first command.
  std::size_t pos = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  while (pos <= text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string_view line(text.data() + pos, eol - pos);
    pos = eol + 1;
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);  // CRLF files
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    std::vector<std::string_view> words = splitWords(line);
    if (words.empty()) continue;
    LineParser p(script.path, lineNo, std::move(words));
    ScriptCommand c = parseLine(p);
    c.line = lineNo;
    if (c.op == ScriptOp::Start) {
      if (started) p.fail("start", "the viewer is already placed (`start` may appear once)");
      if (moved) p.fail("start", "comes after a motion; `start` must come before any motion");
      started = true;
    }
    if (isMotion(c.op)) moved = true;
    script.commands.push_back(std::move(c));
  }
  return script;
}

}  // namespace nestwalk
