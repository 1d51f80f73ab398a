//! Exporters: each test proves what the exported numbers mean.
