#pragma once
// The two error paths of sphdem (STYLE habit 12):
//  - InputError: a bad case file or command line. Every rank reads the same
//    input and so throws the same error; the app prints it once (rank 0) and
//    every rank exits with status 2 before anything is written.
//  - SimulationError: the run cannot continue (NaN, particle outside the
//    domain). The solver writes the last state, then the app exits with 3.
#include <stdexcept>
#include <string>

namespace sphdem {

class InputError : public std::runtime_error {
 public:
  // file: the case file (or "--set"), line: 1-based (0 when unknown),
  // key: dotted path of the offending key.
  InputError(std::string file, int line, std::string key, const std::string& what);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
};

class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace sphdem
