// Compiles tests/test_pch.h once; every test program reuses the result.
