// SPDX-License-Identifier: MIT
#pragma once

#include <stdexcept>
#include <string>

namespace sonarsynth {

/// Base of every exception sonarsynth throws. Messages start with the component
/// ("xtf reader: ...", "scene: ...") and name the file, field and value concerned.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Invalid user input: a configuration value, a scene key, a command-line option.
class InputError : public Error {
 public:
  using Error::Error;
};

/// A file that cannot be read or written, or whose bytes do not follow its format.
class FormatError : public Error {
 public:
  using Error::Error;
};

}  // namespace sonarsynth
