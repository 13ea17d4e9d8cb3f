"""Code the tests share: checkers of meshes and runs, test cases, paths.  No tests here."""
