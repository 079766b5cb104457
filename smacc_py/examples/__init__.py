"""Runnable examples that the README shows; tests run them, so the README's code keeps working."""
