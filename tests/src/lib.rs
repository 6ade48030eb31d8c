//! System tests and benchmarks of the motion suite (see tests/ and src/bin/).
