from lenslab.cli.main import console

console()
