// Constraint stage: see constraints.hpp (issue 4).
