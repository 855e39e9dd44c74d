"""Tables, plots, animations and reports made from results (matplotlib/plotly imported lazily)."""
