"""Every command a person types, one module each: its arguments, its printing, its exit code.

The work is in the libraries below (a notebook's widget calls the same functions); nothing in the
package imports an app. The list, with the make target that starts each: docs/commands.md.
"""
