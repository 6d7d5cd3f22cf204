"""Every command a person types, one module each: its arguments, its printing, its exit code.

The work is in the libraries below (a notebook's widget calls the same functions); nothing in
the package imports an app. ``python -m hri_teleop.apps.<name> --help`` for each:

========================  ==========================  ====================================================
module                    started by                  what it does
========================  ==========================  ====================================================
``demo``                  ``make demo``               the whole lab simulated, then its summary and plot
``demo_sensor``           ``make demo-sensor``        sensor.launch with a simulated press, recorded
``doctor``                ``make doctor``             a lab station's preflight, one line per part
``lab``                   ``make lab``                JupyterLab on the notebooks with the course's kernel
``lab_twin``              ``make lab-twin``           a master that looks like the lab PC's, counting
``pad_check``             (by hand)                   a pad's raw and named input live, its layout
``calibrate``             (by hand)                   the board's maximum count while the piston is pressed
``simavr_board``          (by hand)                   the firmware on a simulated Uno with a pty
``trial``                 Ex. 14                      plan, record, outcome, TLX, rehearse, analyse
``course``                ``make release``, ...       the instructor's course commands (release, strip, ...)
``grade``                 ``hri-grade``, ``make grade``  grade a submission, a folder, an nbgrader course
``gradescope``            ``make gradescope``         build the Gradescope autograder zip
``selfcheck``             ``make check`` (bundle)     run a student's notebooks and show their points
``files_check``           ``make check`` (bundle)     grade the assignment folders' hri_lab files
========================  ==========================  ====================================================
"""
