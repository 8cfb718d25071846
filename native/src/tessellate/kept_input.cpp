// InputTopology, the handle to what a build kept (KeptInput, inline in kept_input.h) for the next cut of a mesh.
#include "tessellate/kept_input.h"

namespace loopsub {

InputTopology::InputTopology() = default;
InputTopology::~InputTopology() = default;
InputTopology::InputTopology(const InputTopology&) = default;
InputTopology& InputTopology::operator=(const InputTopology&) = default;
bool InputTopology::empty() const { return !parts_; }

}  // namespace loopsub
