# `comlearn experiments`: the paper tables and figures (tests added with the implementation).
