import sys

from lenslab.cli.main import main

sys.exit(main())
