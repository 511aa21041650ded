#include "core/obj_reader.hpp"

#include "core/input_file.hpp"

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace drape {
namespace {

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

bool isDigit(char c) {
  return c >= '0' && c <= '9';
}

// The words of one statement, split at any run of blanks (spaces and tabs alike).
class Words {
 public:
  explicit Words(std::string_view line) : rest_(line) {}
  bool next(std::string_view& word) {
    std::size_t begin = 0;
    while (begin < rest_.size() && isBlank(rest_[begin]))
      ++begin;
    if (begin == rest_.size()) return false;
    std::size_t end = begin;
    while (end < rest_.size() && !isBlank(rest_[end]))
      ++end;
    word = rest_.substr(begin, end - begin);
    rest_.remove_prefix(end);
    return true;
  }

 private:
  std::string_view rest_;
};

// A word as a message shows it: quoted, control and non-ASCII bytes escaped, long ones cut, so that the
// message stays one readable line whatever the file holds.
std::string shown(std::string_view word) {
  std::string out = "'";
  for (std::size_t i = 0; i < word.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(word[i]);
    if (c >= 0x20 && c < 0x7f && c != '\'') {
      out += char(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  return out + (word.size() > 40 ? "...'" : "'");
}

// [+-]? (D+ (. D*)? | . D+) ([eE] [+-]? D+)? : the numbers OBJ writers write, and nothing strtod would
// also take (nan, inf, hex, a trailing letter).
bool isDecimal(std::string_view s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t digits = 0;
  for (; i < s.size() && isDigit(s[i]); ++i)
    ++digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    for (; i < s.size() && isDigit(s[i]); ++i)
      ++digits;
  }
  if (digits == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    const std::size_t exponent = i;
    for (; i < s.size() && isDigit(s[i]); ++i) {
    }
    if (i == exponent) return false;
  }
  return i == s.size();
}

// What strtod reads as infinite or NaN: said to be "not finite", which is what the user meant to write.
bool spellsNonFinite(std::string_view s) {
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.remove_prefix(1);
  std::string lower;
  for (char c : s.substr(0, 8))
    lower += char(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  return lower.rfind("nan", 0) == 0 || lower.rfind("inf", 0) == 0;
}

struct Corner {
  long long v = 0, t = 0, n = 0;  // as written; 0 where absent
};

class ObjParser {
 public:
  explicit ObjParser(const ObjLimits& limits) : limits_(limits) {}

  void line(std::string_view text) {
    ++line_;
    if (text.size() > kMaxObjLineBytes) tooLong();
    if (const std::size_t hash = text.find('#'); hash != std::string_view::npos) text = text.substr(0, hash);
    Words words(text);
    std::string_view keyword;
    if (!words.next(keyword)) return;
    if (keyword == "v")
      vertex(words);
    else if (keyword == "vt")
      texcoord(words);
    else if (keyword == "vn")
      normal(words);
    else if (keyword == "f")
      face(words);
  }

  [[noreturn]] void tooLong() const {
    fail("longer than " + describeBytes(static_cast<long long>(kMaxObjLineBytes)) + " (not an OBJ statement)");
  }

  PolygonMesh finish() {
    if (mesh_.faces.empty()) throw MeshError("no faces (a mesh needs at least one 'f' line)");
    if (any_uv_) {
      mesh_.uvs.assign(mesh_.positions.size(), glm::vec2(0.0f));
      for (std::size_t v = 0; v < uv_of_.size(); ++v)
        if (uv_of_[v] >= 0) mesh_.uvs[v] = texcoords_[std::size_t(uv_of_[v])];
    }
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw MeshError("line " + std::to_string(line_) + ": " + problem);
  }

  double number(std::string_view word, const char* what) const {
    if (!isDecimal(word))
      fail(std::string(what) + " " + shown(word) +
           (spellsNonFinite(word) ? " is not a finite number" : " is not a number"));
    const std::string text(word);
    const double v = std::strtod(text.c_str(), nullptr);
    if (!std::isfinite(v))
      fail(std::string(what) + " " + shown(word) + " is not a finite number (beyond double range)");
    return v;
  }

  // At least `least` and at most `most` numbers, each checked; returns how many.
  int numbers(Words& words, double* out, int least, int most, const char* what, const char* shape) const {
    int count = 0;
    std::string_view word;
    while (words.next(word)) {
      if (count == most) fail(std::string("too many numbers: ") + shape);
      out[count++] = number(word, what);
    }
    if (count < least) fail(shape);
    return count;
  }

  void vertex(Words& words) {
    double x[6];
    // x y z, x y z w, or x y z r g b (a colour some writers add).
    const int count = numbers(words, x, 3, 6, "vertex coordinate", "a vertex needs x, y and z (then w, or r g b)");
    if (count == 5) fail("a vertex is x y z, x y z w or x y z r g b; this one has 5 numbers");
    if ((long long)mesh_.positions.size() == limits_.vertices)
      fail("more than " + std::to_string(limits_.vertices) + " vertices" + limits_.vertices_note);
    mesh_.positions.emplace_back(x[0], x[1], x[2]);
    uv_of_.push_back(-1);
  }

  void texcoord(Words& words) {
    double uv[3] = {0, 0, 0};
    numbers(words, uv, 1, 3, "texture coordinate", "a texture coordinate needs u (then v and w)");
    if ((long long)texcoords_.size() == limits_.corners())
      fail("more than " + std::to_string(limits_.corners()) + " texture coordinates");
    texcoords_.emplace_back(float(uv[0]), float(uv[1]));
  }

  void normal(Words& words) {
    double n[3];
    numbers(words, n, 3, 3, "normal coordinate", "a normal needs x, y and z");
    ++normals_;
  }

  // A whole number as written, [+-]?D+; beyond 10^15 it is kept at that (no index is so large).
  bool index(std::string_view s, long long& out) const {
    std::size_t i = 0;
    const bool negative = !s.empty() && s[0] == '-';
    if (!s.empty() && (s[0] == '+' || s[0] == '-')) ++i;
    if (i == s.size()) return false;
    long long v = 0;
    for (; i < s.size(); ++i) {
      if (!isDigit(s[i])) return false;
      if (v < 1000000000000000LL) v = v * 10 + (s[i] - '0');
    }
    out = negative ? -v : v;
    return true;
  }

  Corner corner(std::string_view word) const {
    Corner c;
    const std::size_t slash = word.find('/');
    const std::string_view v = word.substr(0, slash);
    bool ok = index(v, c.v);
    if (ok && slash != std::string_view::npos) {
      const std::string_view rest = word.substr(slash + 1);
      const std::size_t second = rest.find('/');
      const std::string_view t = rest.substr(0, second);
      if (second == std::string_view::npos)
        ok = index(t, c.t);  // v/vt
      else
        ok = (t.empty() || index(t, c.t)) && index(rest.substr(second + 1), c.n);  // v//vn, v/vt/vn
    }
    if (!ok) fail("face corner " + shown(word) + " is not v, v/vt, v//vn or v/vt/vn in whole numbers");
    return c;
  }

  // The 0-based index that `written` names among `count` items read so far (negative counts back from the
  // last). Only what came before the face may be named, so every corner can be checked on its line.
  std::size_t resolve(std::string_view word, long long written, long long count, const char* what) const {
    if (written == 0) fail("face corner " + shown(word) + " names " + what + " 0 (OBJ counts from 1)");
    const long long i = written > 0 ? written - 1 : count + written;
    if (i < 0 || i >= count)
      fail("face corner " + shown(word) + " names " + what + " " + std::to_string(written) + ", but " +
           (count == 0 ? std::string("none") : "only " + std::to_string(count)) + " come before this line");
    return std::size_t(i);
  }

  void face(Words& words) {
    std::vector<std::uint32_t> face;
    std::string_view word;
    while (words.next(word)) {
      if (corners_ == limits_.corners())
        fail("more than " + std::to_string(limits_.corners()) + " face corners in all" + limits_.vertices_note);
      ++corners_;
      const Corner c = corner(word);
      const std::size_t v = resolve(word, c.v, (long long)mesh_.positions.size(), "vertex");
      if (c.t != 0) {
        const std::size_t t = resolve(word, c.t, (long long)texcoords_.size(), "texture coordinate");
        if (uv_of_[v] < 0) uv_of_[v] = (long long)t;
        any_uv_ = true;
      }
      if (c.n != 0) resolve(word, c.n, normals_, "normal");
      face.push_back(std::uint32_t(v));
    }
    if (face.empty()) fail("a face needs corners ('f' alone)");
    if ((long long)mesh_.faces.size() == limits_.faces())
      fail("more than " + std::to_string(limits_.faces()) + " faces" + limits_.vertices_note);
    mesh_.faces.push_back(std::move(face));
  }

  ObjLimits limits_;
  long long line_ = 0;
  PolygonMesh mesh_;
  std::vector<glm::vec2> texcoords_;
  std::vector<long long> uv_of_;  // per vertex: the texcoord of its first corner that has one, or -1
  bool any_uv_ = false;
  long long normals_ = 0;
  long long corners_ = 0;
};

}  // namespace

PolygonMesh parseObj(std::string_view text, const ObjLimits& limits) {
  ObjParser parser(limits);
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    parser.line(text.substr(0, end));
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
  }
  return parser.finish();
}

PolygonMesh readObj(const std::filesystem::path& file, const ObjLimits& limits) {
  try {
    InputFile in(file, kMaxObjBytes, "an OBJ file");
    ObjParser parser(limits);
    // Line by line as the bytes arrive: memory holds what the mesh keeps, never the file's text.
    std::string pending;
    std::vector<char> piece(1 << 20);
    while (const std::size_t n = in.read(piece.data(), piece.size())) {
      pending.append(piece.data(), n);
      std::size_t begin = 0;
      for (std::size_t end; (end = pending.find('\n', begin)) != std::string::npos; begin = end + 1)
        parser.line(std::string_view(pending).substr(begin, end - begin));
      pending.erase(0, begin);
      if (pending.size() > kMaxObjLineBytes) parser.line(pending);  // refused as too long, with its number
    }
    if (!pending.empty()) parser.line(pending);
    return parser.finish();
  } catch (const InputError& e) {
    throw MeshError(e.what());
  }
}

void checkFloatRange(const std::vector<glm::dvec3>& positions) {
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::dvec3& p = positions[i];
    if (!(std::fabs(p.x) <= double(FLT_MAX) && std::fabs(p.y) <= double(FLT_MAX) &&
          std::fabs(p.z) <= double(FLT_MAX))) {
      char most[32];
      std::snprintf(most, sizeof most, "%.9g", double(FLT_MAX));
      throw MeshError("vertex " + std::to_string(i) + " is beyond float range (|coordinate| at most " + most + ")");
    }
  }
}

}  // namespace drape
