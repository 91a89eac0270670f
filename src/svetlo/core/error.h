// The one error type that reaches the command line. It names the file, the place in it (a
// JSON path such as `objects[3].radius`, a line number, a flag) and what is wrong; the CLI
// prints it as `svetlo: error: FILE: WHERE: WHAT`.
#pragma once

#include <stdexcept>
#include <string>

namespace svetlo {

class Error : public std::runtime_error {
public:
    Error(std::string file, std::string where, std::string what)
        : std::runtime_error(file + ": " + where + ": " + what),
          file_(std::move(file)),
          where_(std::move(where)),
          what_(std::move(what)) {}

    const std::string& file() const { return file_; }
    const std::string& where() const { return where_; }
    const std::string& message() const { return what_; }

private:
    std::string file_, where_, what_;
};

}  // namespace svetlo
