// The page's stylesheet and scripts: report/assets/, compiled in (CMakeLists.txt, hunav_embed_files).
#include "hunav/report/assets.hpp"

#include "hunav/embedded_files.hpp"

namespace hunav::report::assets {

extern const EmbeddedFiles kFiles;

const std::string& css() {
  static const std::string text(kFiles.text("report.css"));
  return text;
}
const std::string& commonJs() {
  static const std::string text(kFiles.text("common.js"));
  return text;
}
const std::string& runJs() {
  static const std::string text(kFiles.text("run.js"));
  return text;
}
const std::string& batchJs() {
  static const std::string text(kFiles.text("batch.js"));
  return text;
}

}  // namespace hunav::report::assets
