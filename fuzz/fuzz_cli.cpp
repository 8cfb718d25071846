// libFuzzer target: the loopsub command line. The bytes are split at NUL into arguments; parsing either gives a
// command or a UsageError (exit 2 in the CLI), never anything else.
#include <cstdint>
#include <string>
#include <vector>

#include "command_line.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<std::string> words(1, "loopsub");
    words.emplace_back();
    for (std::size_t i = 0; i < size; ++i) {
        if (data[i] == 0) words.emplace_back();
        else words.back().push_back(char(data[i]));
    }
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    argv.push_back(nullptr);
    try {
        loopsub::cli::parse_command_line(int(words.size()), argv.data());
    } catch (const loopsub::cli::UsageError&) {}
    return 0;
}
