#pragma once
/// @file errors.hpp
/// Typed exceptions thrown by the granular API. Every message names what was wrong (file, field,
/// value, size) so a user can act on it. An operation that throws leaves the world as it was.

#include <stdexcept>
#include <string>

namespace granular {

/// Base of every error granular throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An argument is out of its valid range (zero or negative size, unknown material, tool region
/// outside the grid, NaN radius...).
class InvalidArgument : public Error {
 public:
  using Error::Error;
};

/// A requested allocation (grid, table) does not fit in memory; the message gives the sizes.
class OutOfMemory : public Error {
 public:
  using Error::Error;
};

/// A file could not be opened, read or written.
class FileError : public Error {
 public:
  using Error::Error;
};

/// A file was read but its content is malformed, truncated or inconsistent. The message names the
/// file and the field or byte offset.
class ParseError : public Error {
 public:
  using Error::Error;
};

/// The object cannot take the call in its present state (a World that was moved from).
class StateError : public Error {
 public:
  using Error::Error;
};

/// A compute backend failed or is unavailable (no GPU, driver error).
class BackendError : public Error {
 public:
  using Error::Error;
};

/// The ranks of a distributed world could not exchange cells (a rank failed, a transport error, a
/// message of the wrong size); distributed_world.hpp.
class CommunicatorError : public Error {
 public:
  using Error::Error;
};

}  // namespace granular

namespace granular {

/// A rule set produced an invalid transition table (not a permutation, a moved solid cell...).
class RuleError : public Error {
 public:
  using Error::Error;
};

}  // namespace granular
