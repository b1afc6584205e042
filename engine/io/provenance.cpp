#include "engine/io/provenance.hpp"

#include <pwd.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <ctime>

namespace granflow {

namespace {

std::string& command_line_storage() {
  static std::string text;
  return text;
}

// Quotes an argument the way a POSIX shell would read it back.
std::string shell_quoted(const std::string& argument) {
  if (!argument.empty() && argument.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                      "0123456789_-./=:,+@%") == std::string::npos)
    return argument;
  std::string out = "'";
  for (char c : argument) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

void record_command_line(int argc, const char* const* argv) {
  std::string text;
  for (int k = 0; k < argc; ++k) {
    if (k) text += ' ';
    text += shell_quoted(argv[k]);
  }
  command_line_storage() = text;
}

const std::string& recorded_command_line() { return command_line_storage(); }

std::string host_name() {
  std::array<char, 256> name{};
  if (gethostname(name.data(), name.size() - 1) != 0) return "unknown";
  return name.data();
}

std::string user_name() {
  if (const passwd* entry = getpwuid(geteuid()); entry && entry->pw_name) return entry->pw_name;
  if (const char* name = std::getenv("USER")) return name;
  return "unknown";
}

std::string utc_timestamp() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm parts{};
  gmtime_r(&now, &parts);
  std::array<char, 32> text{};
  std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%SZ", &parts);
  return text.data();
}

int thread_limit() {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

namespace {
int recorded_ranks = 1;
}  // namespace

void record_rank_count(int ranks) { recorded_ranks = ranks; }
int rank_count() { return recorded_ranks; }

}  // namespace granflow
