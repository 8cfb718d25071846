// The names of option values (loopsub::option_names), the one table the CLI, the Python module and the add-on use,
// and the byte sizes of the memory messages (loopsub::describe_bytes).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "loopsub/loopsub.h"

namespace {

template <typename Option>
std::vector<std::string> names_of() {
    const loopsub::OptionNames table = loopsub::option_names<Option>();
    return {table.begin(), table.end()};
}

// Every name parses to the value it names, and back; other text leaves the value alone.
template <typename Option>
void expect_round_trips() {
    const loopsub::OptionNames table = loopsub::option_names<Option>();
    ASSERT_GT(table.count, 1);
    for (int i = 0; i < table.count; ++i) {
        Option value = Option(i == 0 ? 1 : 0);
        EXPECT_TRUE(loopsub::parse_option(table.names[i], value)) << table.names[i];
        EXPECT_EQ(int(value), i) << table.names[i];
        EXPECT_STREQ(loopsub::option_name(Option(i)), table.names[i]);
    }
    for (const char* other : {"", "Hoppe94", "edges ", "corners_plus1", "AUTO", "x"}) {
        Option value = Option(1);
        EXPECT_FALSE(loopsub::parse_option(other, value)) << other;
        EXPECT_EQ(int(value), 1) << other;
    }
}

TEST(OptionNames, EachOptionHasItsNamesInTheOrderOfItsEnum) {
    EXPECT_EQ(names_of<loopsub::Rules>(), (std::vector<std::string>{"hoppe94", "opensubdiv"}));
    EXPECT_EQ(names_of<loopsub::Boundary>(), (std::vector<std::string>{"edges", "edges-and-corners", "none"}));
    EXPECT_EQ(names_of<loopsub::CreaseMethod>(), (std::vector<std::string>{"uniform", "chaikin"}));
    EXPECT_EQ(names_of<loopsub::FaceVaryingInterpolation>(),
              (std::vector<std::string>{"none", "corners", "corners-plus1", "corners-plus2", "boundaries", "all"}));
    EXPECT_EQ(names_of<loopsub::LevelTables>(), (std::vector<std::string>{"auto", "stored", "derived"}));
    EXPECT_STREQ(loopsub::option_name(loopsub::Boundary::EdgesAndCorners), "edges-and-corners");
    EXPECT_STREQ(loopsub::option_name(loopsub::FaceVaryingInterpolation::CornersOnly), "corners");
}

TEST(OptionNames, NamesAndValuesRoundTrip) {
    expect_round_trips<loopsub::Rules>();
    expect_round_trips<loopsub::Boundary>();
    expect_round_trips<loopsub::CreaseMethod>();
    expect_round_trips<loopsub::FaceVaryingInterpolation>();
    expect_round_trips<loopsub::LevelTables>();
}

TEST(OptionNames, ListedForMessages) {
    EXPECT_EQ(loopsub::option_names<loopsub::Rules>().listed(), "hoppe94 or opensubdiv");
    EXPECT_EQ(loopsub::option_names<loopsub::Boundary>().listed("'"), "'edges', 'edges-and-corners' or 'none'");
}

TEST(DescribeBytes, MiBBelowOneGiBThenGiB) {
    EXPECT_EQ(loopsub::describe_bytes(0), "0.00 MiB (0 bytes)");
    EXPECT_EQ(loopsub::describe_bytes(489684798), "467.00 MiB (489684798 bytes)");
    EXPECT_EQ(loopsub::describe_bytes((std::uint64_t(1) << 30) - 1), "1024.00 MiB (1073741823 bytes)");
    EXPECT_EQ(loopsub::describe_bytes(std::uint64_t(3) << 29), "1.50 GiB (1610612736 bytes)");
}

}  // namespace
