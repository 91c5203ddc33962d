// The tests call cellfx's namespaces by their short names. A game does not: everything cellfx
// declares is under cellfx:: (cellfx::fx, cellfx::terrain), so a game's own fx or terrain
// cannot clash with it (tests/consumer proves that).
#pragma once

namespace cellfx::fx {}
namespace cellfx::terrain {}

namespace fx = cellfx::fx;
namespace terrain = cellfx::terrain;
