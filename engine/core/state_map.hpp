#pragma once
// The saved state of anything that continues a run: named flat arrays of
// doubles. Every value a checkpoint holds (integers up to 2^53, indices,
// counters) is exact in a double, so one array type serves all, and a
// checkpoint file is a list of such arrays.

#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace granflow {

using StateMap = std::map<std::string, std::vector<double>>;

// An object that a checkpoint saves and a resumed run restores: the
// event-driven gas, a correlator, an observer's reference data.
class Stateful {
 public:
  virtual ~Stateful() = default;
  virtual StateMap save_state() const = 0;
  virtual void restore_state(const StateMap& state) = 0;
  // Arrays of save_state() that hold one row per item of this rank's part
  // (its particles, their pairs) where it holds a part of a system spread
  // over ranks: name -> its row count. A checkpoint written by rank puts
  // the ranks' rows one after another, as it does the particles'.
  virtual std::map<std::string, std::size_t> state_rows() const { return {}; }
};

// The entries of `state` under "prefix/", with the prefix removed.
inline StateMap state_under(const StateMap& state, const std::string& prefix) {
  StateMap out;
  const std::string head = prefix + "/";
  for (auto it = state.lower_bound(head); it != state.end() && it->first.compare(0, head.size(), head) == 0; ++it)
    out.emplace(it->first.substr(head.size()), it->second);
  return out;
}

// Texts (command lines, host names) as one array of their bytes, each text
// ended by a 0, and back.
inline std::vector<double> encode_texts(const std::vector<std::string>& texts) {
  std::vector<double> out;
  for (const auto& text : texts) {
    for (unsigned char c : text) out.push_back(c);
    out.push_back(0.0);
  }
  return out;
}
inline std::vector<std::string> decode_texts(const std::vector<double>& bytes) {
  std::vector<std::string> texts;
  std::string current;
  for (double b : bytes) {
    if (!(b >= 0.0 && b < 256.0)) throw std::invalid_argument("checkpoint text holds a value that is not a byte");
    if (b == 0.0) {
      texts.push_back(current);
      current.clear();
    } else {
      current.push_back(static_cast<char>(static_cast<unsigned char>(b)));
    }
  }
  return texts;
}

// A list of fixed-size vectors (Eigen's Vec<D>) as one flat array and back.
template <class V>
std::vector<double> flatten_vectors(const std::vector<V>& vectors) {
  std::vector<double> flat;
  flat.reserve(vectors.size() * static_cast<std::size_t>(V::RowsAtCompileTime));
  for (const auto& v : vectors) flat.insert(flat.end(), v.data(), v.data() + V::RowsAtCompileTime);
  return flat;
}
// `what` names the data in the error when the sizes differ.
template <class V>
void unflatten_vectors(const std::vector<double>& flat, std::vector<V>& vectors, const std::string& what) {
  constexpr auto width = static_cast<std::size_t>(V::RowsAtCompileTime);
  if (flat.size() != vectors.size() * width)
    throw std::invalid_argument("checkpoint " + what + " has " + std::to_string(flat.size()) + " values, expected " +
                                std::to_string(vectors.size() * width));
  for (std::size_t i = 0; i < vectors.size(); ++i)
    for (std::size_t a = 0; a < width; ++a) vectors[i][static_cast<int>(a)] = flat[i * width + a];
}

inline void put_state_under(StateMap& state, const std::string& prefix, const StateMap& part) {
  for (const auto& [name, values] : part) state[prefix + "/" + name] = values;
}

}  // namespace granflow
