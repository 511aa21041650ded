#include "app/suggest.hpp"

#include <algorithm>

namespace drape {

int editDistance(const std::string& a, const std::string& b) {
  // Damerau-Levenshtein, restricted (optimal string alignment): "verison" is one swap from "version".
  std::vector<std::vector<int>> d(a.size() + 1, std::vector<int>(b.size() + 1, 0));
  for (std::size_t i = 0; i <= a.size(); ++i)
    d[i][0] = int(i);
  for (std::size_t j = 0; j <= b.size(); ++j)
    d[0][j] = int(j);
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

std::string closestWord(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  int best_distance = std::min(2, std::max(1, int(word.size()) / 3)) + 1;
  for (const std::string& c : candidates) {
    const int distance = editDistance(word, c);
    if (distance < best_distance) {
      best = c;
      best_distance = distance;
    }
  }
  return best;
}

namespace {

// Every name the command's options answer to, with their dashes: --frames, -f, ...
std::vector<std::string> optionNames(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& n : option->get_lnames())
      names.push_back("--" + n);
    for (const std::string& n : option->get_snames())
      names.push_back("-" + n);
  }
  return names;
}

}  // namespace

std::string unknownOptionMessage(const CLI::App& command, const std::vector<std::string>& args) {
  const std::vector<std::string> known = optionNames(command);
  for (const std::string& arg : args) {
    if (arg.size() < 2 || arg[0] != '-' || arg == "--") continue;
    if (arg[1] != '-' && std::isdigit(static_cast<unsigned char>(arg[1]))) continue;  // a negative number
    const std::string name = arg.substr(0, arg.find('='));
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    const std::string near = closestWord(name, known);
    return "unknown option " + name + (near.empty() ? "" : " (did you mean " + near + "?)");
  }
  return {};
}

}  // namespace drape
