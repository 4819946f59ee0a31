"""Compiler stages: flatten → simplify → index reduction → code generation (+ cache)."""
