// expr/input_error.h — certray::InputError: bad user input, with the file, line and column where it
// was found.
//
// Contract: thrown by every reader of user input (the .expr parser, the .vm importer, scene and ray
// files); only apps/ and bindings catch it. what() reads "file:line:col: message"; a line of 0
// means the error concerns the whole file (e.g. it cannot be opened) and what() reads "file:
// message".
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace certray {

/// Bad user input. `line` and `column` are 1-based; line 0 means "the whole file".
class InputError : public std::runtime_error {
  public:
    /// Builds the error; what() is "file:line:col: message" (or "file: message" when line == 0).
    InputError(std::string file, int line, int column, std::string message)
        : std::runtime_error(format(file, line, column, message)),
          file_(std::move(file)),
          line_(line),
          column_(column),
          message_(std::move(message)) {}

    /// The file name as given by the caller (e.g. "<string>" for in-memory text).
    const std::string& file() const noexcept { return file_; }
    /// The 1-based line, or 0 when the error concerns the whole file.
    int line() const noexcept { return line_; }
    /// The 1-based column (in bytes), or 0 when unknown.
    int column() const noexcept { return column_; }
    /// The message alone, without the location prefix.
    const std::string& message() const noexcept { return message_; }

  private:
    static std::string format(const std::string& file, int line, int column,
                              const std::string& message) {
        if (line <= 0) return file + ": " + message;
        return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message;
    }

    std::string file_;
    int line_;
    int column_;
    std::string message_;
};

}  // namespace certray
