// The CSV writer of every command of this project: a header line, then rows of text and numbers (RFC 4180
// quoting; numbers to 6 significant digits, NaN as an empty cell).
#ifndef FCL_RS_TOOLS_COMMON_CSV_WRITER_H
#define FCL_RS_TOOLS_COMMON_CSV_WRITER_H

#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace fcl_rs {
namespace tools {

class CsvWriter
{
public:
  /// One cell: text, or a number (integers exactly, others with %.6g).
  class Cell
  {
  public:
    Cell(const std::string& text) : text_(quoted(text)) {}
    Cell(const char* text) : text_(quoted(text)) {}
    template <typename T, typename = std::enable_if_t<std::is_arithmetic<T>::value>>
    Cell(T value) : text_(number(value))
    {
    }
    const std::string& text() const { return text_; }

  private:
    static std::string quoted(const std::string& s)
    {
      if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
      std::string q = "\"";
      for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
      return q + '"';
    }
    template <typename T>
    static std::string number(T value)
    {
      if constexpr (std::is_integral<T>::value)
        return std::to_string(value);
      else
      {
        if (std::isnan(value)) return "";
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.6g", double(value));
        return buf;
      }
    }
    std::string text_;
  };

  /// Opens path for writing (throws std::runtime_error naming it otherwise) and writes the header.
  CsvWriter(const std::string& path, const std::vector<std::string>& columns) : path_(path), columns_(columns.size())
  {
    out_.open(path);
    if (!out_) throw std::runtime_error("cannot write CSV file '" + path + "'");
    std::vector<Cell> header(columns.begin(), columns.end());
    write(header);
  }

  /// One row with as many cells as the header has columns.
  void row(std::initializer_list<Cell> cells) { write(std::vector<Cell>(cells)); }
  void row(const std::vector<Cell>& cells) { write(cells); }

  /// Flushes and reports a write error (a full disk) as std::runtime_error.
  void close()
  {
    out_.close();
    if (!out_) throw std::runtime_error("error writing CSV file '" + path_ + "'");
  }

  const std::string& path() const { return path_; }

private:
  void write(const std::vector<Cell>& cells)
  {
    if (cells.size() != columns_)
      throw std::logic_error("CSV row of " + std::to_string(cells.size()) + " cells for " + std::to_string(columns_) +
                             " columns in '" + path_ + "'");
    for (std::size_t i = 0; i < cells.size(); ++i) out_ << (i ? "," : "") << cells[i].text();
    out_ << '\n';
  }

  std::string path_;
  std::size_t columns_;
  std::ofstream out_;
};

}  // namespace tools
}  // namespace fcl_rs

#endif
