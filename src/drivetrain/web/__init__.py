"""The local web app (``drivetrain serve``): a JSON API and one page, on the same engine as the CLI.

``drivetrain.web.app.create_app`` builds the FastAPI application; ``drivetrain.web.store`` keeps
projects in SQLite. Importing this package does not import FastAPI.
"""
