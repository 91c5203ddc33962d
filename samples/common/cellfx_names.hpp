// The samples and the cellfx command call cellfx's namespaces by their short names, as a game
// may in its own files: everything cellfx declares is under cellfx:: (cellfx::fx,
// cellfx::terrain), and these aliases are the samples' own choice, not cellfx's.
#pragma once

namespace cellfx::fx {}
namespace cellfx::terrain {}
namespace cellfx::verify {} // the benches' image comparison (testing/verify)

namespace fx = cellfx::fx;
namespace terrain = cellfx::terrain;
namespace verify = cellfx::verify;
