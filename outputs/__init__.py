"""What a run leaves for people: results folders, history files, summary.json,
plots, VTK series, fpd render, the test machine's cycles, folder claims. May
import coupling and below."""
