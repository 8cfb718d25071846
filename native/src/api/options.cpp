// The names of the options' values: the one table the command line, the Python module and the add-on read them from.
#include <iterator>

#include "loopsub/loopsub.h"
#include "loopsub/tessellation.h"

namespace loopsub {

namespace {

// Each list in its enum's order.
constexpr const char* kRules[] = {"hoppe94", "opensubdiv"};
constexpr const char* kBoundaries[] = {"edges", "edges-and-corners", "none"};
constexpr const char* kCreaseMethods[] = {"uniform", "chaikin"};
// OpenSubdiv's FVarLinearInterpolation, LINEAR_NONE to LINEAR_ALL.
constexpr const char* kFaceVaryingInterpolations[] = {"none",          "corners",    "corners-plus1",
                                                      "corners-plus2", "boundaries", "all"};
constexpr const char* kLevelTables[] = {"auto", "stored", "derived"};
constexpr const char* kDicingMeasures[] = {"length", "deviation"};
static_assert(std::size(kRules) == std::size_t(Rules::OpenSubdiv) + 1 &&
                  std::size(kBoundaries) == std::size_t(Boundary::None) + 1 &&
                  std::size(kCreaseMethods) == std::size_t(CreaseMethod::Chaikin) + 1 &&
                  std::size(kFaceVaryingInterpolations) == std::size_t(FaceVaryingInterpolation::All) + 1 &&
                  std::size(kLevelTables) == std::size_t(LevelTables::Derived) + 1 &&
                  std::size(kDicingMeasures) == std::size_t(DicingMeasure::Deviation) + 1,
              "a name for every value of each option");

template <std::size_t N>
OptionNames table(const char* const (&names)[N]) {
    return {names, int(N)};
}

// The table of each option, picked by its type.
OptionNames table_of(Rules) { return table(kRules); }
OptionNames table_of(Boundary) { return table(kBoundaries); }
OptionNames table_of(CreaseMethod) { return table(kCreaseMethods); }
OptionNames table_of(FaceVaryingInterpolation) { return table(kFaceVaryingInterpolations); }
OptionNames table_of(LevelTables) { return table(kLevelTables); }
OptionNames table_of(DicingMeasure) { return table(kDicingMeasures); }

}  // namespace

std::string OptionNames::listed(const char* quote) const {
    std::string text;
    for (int i = 0; i < count; ++i) {
        if (i > 0) text += i + 1 < count ? ", " : " or ";
        text += quote;
        text += names[i];
        text += quote;
    }
    return text;
}

template <typename Option>
OptionNames option_names() {
    return table_of(Option{});
}
template OptionNames option_names<Rules>();
template OptionNames option_names<Boundary>();
template OptionNames option_names<CreaseMethod>();
template OptionNames option_names<FaceVaryingInterpolation>();
template OptionNames option_names<LevelTables>();
template OptionNames option_names<DicingMeasure>();

}  // namespace loopsub
