// The C stream the OBJ reader and writer use, closed however they leave.
#pragma once

#include <cstdio>
#include <memory>

namespace loopsub::obj {

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

}  // namespace loopsub::obj
