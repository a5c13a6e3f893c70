#pragma once
// Files compiled into a program by hunav_embed_files (cmake/Embed.cmake): the built-in behavior
// trees, the paper's published means, the report's and the view's web assets, as they were when the
// program was built.
#include <stdexcept>
#include <string>
#include <string_view>

namespace hunav {

struct EmbeddedFile {
  std::string_view name;  // its path relative to the folder it was embedded from
  std::string_view text;
};

class EmbeddedFiles {
 public:
  constexpr EmbeddedFiles(const EmbeddedFile* first, const EmbeddedFile* last) : first_(first), last_(last) {}
  const EmbeddedFile* begin() const { return first_; }
  const EmbeddedFile* end() const { return last_; }
  // The text of `name`; std::out_of_range when it was not embedded (a build error, not bad input).
  std::string_view text(std::string_view name) const {
    for (const EmbeddedFile& f : *this)
      if (f.name == name) return f.text;
    throw std::out_of_range("no embedded file " + std::string(name));
  }

 private:
  const EmbeddedFile* first_;
  const EmbeddedFile* last_;
};

}  // namespace hunav
