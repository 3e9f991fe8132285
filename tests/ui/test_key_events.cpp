// placeholder: replaced by its owner (issue 12)
