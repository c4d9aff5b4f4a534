# `comlearn stack`: planner, simulation, CLI (tests added with the implementation).
