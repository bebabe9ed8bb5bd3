"""Input and output: scene files, result directories, checkpoints, frames, exports, ensembles."""
