"""The report of a MuJoCo check: figures per model and the pages that gather them."""
