#include "tools/bench/result_table.h"

#include "nestwalk/core/number_text.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>

namespace nestwalk::bench {
namespace {

using Pointer = Json::json_pointer;

double numberAt(const Json& row, const std::string& path) {
  const Json& v = row.at(Pointer(path));
  return v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

std::string cellText(const Json& row, const Column& c) {
  const Pointer p(c.path);
  if (!row.contains(p)) return "";
  const Json& v = row.at(p);
  if (v.is_null()) return "-";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_number_integer()) return std::to_string(v.get<long long>()) + c.suffix;
  if (v.is_number_unsigned()) return std::to_string(v.get<unsigned long long>()) + c.suffix;
  return fixedText(v.get<double>(), c.decimals) + c.suffix;
}

void printCell(std::ostream& out, const Column& c, const std::string& text) {
  out << (c.left ? std::left : std::right) << std::setw(c.width) << text;
}

/// The line without its trailing blanks (the cells a row leaves empty).
void printLine(std::ostream& out, const std::string& indent, const std::string& line) {
  out << indent << line.substr(0, line.find_last_not_of(' ') + 1) << "\n";
}

}  // namespace

Json countJson(double count) { return std::isnan(count) ? Json() : Json(static_cast<long long>(count)); }

Table& Table::column(Column c) {
  columns_.push_back(std::move(c));
  return *this;
}

Table& Table::ratio(Column c, std::string numerator, std::string denominator) {
  ratios_.push_back({c.path, std::move(numerator), std::move(denominator)});
  return column(std::move(c));
}

Table Table::againstPeers(Column test, Column set, std::vector<Column> columns, const std::string& group,
                          const std::vector<Peer>& peers, int width, int decimals, int ratioDecimals) {
  Table t;
  t.column(std::move(test)).column(std::move(set));
  for (Column& c : columns) t.column(std::move(c));
  const std::string nestwalk = "/" + group + "/nestwalk";
  t.column({"nestwalk", nestwalk, width, decimals});
  for (const Peer& p : peers) {
    const std::string value = "/" + group + "/" + p.key;
    t.column({p.title, value, width, decimals}).ratio({"ratio", "/ratio/" + p.key, 8, ratioDecimals}, value, nestwalk);
  }
  return t;
}

void Table::add(Json row) {
  for (const Ratio& r : ratios_)
    if (row.contains(Pointer(r.numerator)) && row.contains(Pointer(r.denominator)))
      row[Pointer(r.path)] = jsonNumber(numberAt(row, r.numerator) / numberAt(row, r.denominator));
  rows_.push_back(std::move(row));
}

void Table::addMeasured(Json row, const std::string& group) {
  const Json& values = row[group];
  if (std::any_of(values.begin(), values.end(), [](const Json& v) { return v.is_number(); })) add(std::move(row));
}

void Table::print(std::ostream& out, const std::string& indent) const {
  std::ostringstream title;
  for (const Column& c : columns_) printCell(title, c, c.title);
  printLine(out, indent, title.str());
  for (const Json& row : rows_) {
    std::ostringstream line;
    for (const Column& c : columns_) printCell(line, c, cellText(row, c));
    printLine(out, indent, line.str());
  }
}

Json Table::json() const {
  Json list = Json::array();
  for (Json row : rows_) {
    for (const Column& c : columns_) {
      const Pointer p(c.path);
      if (c.tableOnly && row.contains(p)) row.at(p.parent_pointer()).erase(p.back());
    }
    list.push_back(std::move(row));
  }
  return list;
}

}  // namespace nestwalk::bench
