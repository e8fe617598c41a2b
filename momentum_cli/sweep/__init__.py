"""`momentum sweep`: one problem, many values of its `let` constants, solved as arrays."""
