// The built-in behavior trees: manager/behavior_trees/*.xml, compiled in (CMakeLists.txt,
// hunav_embed_files).
#include <string>
#include <vector>

#include "hunav/embedded_files.hpp"
#include "hunav/manager/hunav_nodes.hpp"

namespace hunav::manager {

extern const EmbeddedFiles kBuiltinTrees;

namespace {
// By behavior code (agent_state_t: 1 regular ... 6 threatening; any other code: regular).
const char* const kNames[] = {"regular.xml", "regular.xml", "impassive.xml",  "surprised.xml",
                              "scared.xml",  "curious.xml", "threatening.xml"};
int indexOf(int behavior) { return behavior >= 1 && behavior <= 6 ? behavior : 1; }
}  // namespace

const char* builtinTreeName(int behavior) { return kNames[indexOf(behavior)]; }

const std::string& builtinTreeXml(int behavior) {
  static const std::vector<std::string> trees = [] {
    std::vector<std::string> texts;
    for (const char* name : kNames) texts.emplace_back(kBuiltinTrees.text(name));
    return texts;
  }();
  return trees[static_cast<std::size_t>(indexOf(behavior))];
}

}  // namespace hunav::manager
