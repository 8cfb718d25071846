// Placeholder until the sse41 path lands: forwards to the scalar reference.
#include "kernels.h"

namespace loopsub::detail {

void refine_sse41(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out, Range v, Range e) {
    refine_scalar(s, in, out, v, e);
}

}  // namespace loopsub::detail
