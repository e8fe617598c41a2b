"""`python -m momentum_cli` runs the command-line interface."""
from .entry import main

if __name__ == "__main__":
    main()
