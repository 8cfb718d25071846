// Files the OBJ tests write and read back, and the float text they compare with.
#pragma once

#include <gtest/gtest.h>

#include <charconv>
#include <chrono>
#include <fstream>
#include <iterator>
#include <string>

namespace loopsub::testing {

// A path in the test temporary directory, named per process: another run of the tests at the same time (a second
// build tree, a second ctest) must not write the same files.
inline std::string temp_path(const std::string& name) {
    static const std::string run = std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
    return ::testing::TempDir() + "loopsub_test_" + run + "_" + name;
}

inline std::string read_text(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

inline void write_text(const std::string& path, const std::string& text) {
    std::ofstream file(path, std::ios::binary);
    file << text;
}

// The text of a float as the OBJ writer must write it: what std::to_chars writes.
inline std::string to_chars_text(float value) {
    char buffer[64];
    return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

}  // namespace loopsub::testing
