// Terrain post-processing and quality statistics (issue 5).
